MODULE Floor
  CONST jointtarget jDown:=[[0,120,60,0,30,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    MoveAbsJ jDown, v500, fine, tool0;
  ENDPROC
ENDMODULE
