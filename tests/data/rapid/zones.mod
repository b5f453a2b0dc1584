MODULE Zones
  VAR speeddata vSlow:=[50,30,5000,1000];
  CONST zonedata zCustom:=[FALSE,25,40,40,4,40,4];
  CONST robtarget pA:=[[900,0,900],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    MoveJ pA, v500, z50, tool0;
    MoveL Offs(pA,0,0,-100), vSlow, zCustom, tool0;
    MoveL pA, v1000, fine, tool0;
  ENDPROC
ENDMODULE
