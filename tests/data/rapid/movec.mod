MODULE Circle
  CONST robtarget pStart:=[[900,-200,900],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pMid:=[[1100,0,900],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pEnd:=[[900,200,900],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    MoveJ pStart, v500, fine, tool0;
    MoveC pMid, pEnd, v200, fine, tool0;
  ENDPROC
ENDMODULE
