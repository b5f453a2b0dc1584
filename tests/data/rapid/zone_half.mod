MODULE ZoneHalf
  ! A 200 mm zone at the corner of two 100 mm MoveL: the controller cuts a zone to half of
  ! either move, so it blends as z50 does (a test swaps z200 for z50 and z40).
  CONST robtarget pA:=[[1000,-50,700],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    ConfJ \Off;
    ConfL \Off;
    MoveJ pA, v1000, fine, tool0;
    MoveL Offs(pA,0,100,0), v500, z200, tool0;
    MoveL Offs(pA,100,100,0), v500, fine, tool0;
  ENDPROC
ENDMODULE
