MODULE OffsRelTool
  CONST robtarget pA:=[[900,0,900],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    MoveJ pA, v500, fine, tool0;
    MoveL Offs(pA,0,100,-50), v200, fine, tool0;
    MoveL RelTool(pA,0,0,50\Rz:=30), v200, fine, tool0;
  ENDPROC
ENDMODULE
