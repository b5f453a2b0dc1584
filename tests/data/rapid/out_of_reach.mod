MODULE Far
  CONST robtarget pFar:=[[3000,0,900],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    MoveJ pFar, v500, fine, tool0;
  ENDPROC
ENDMODULE
