MODULE Unknown
  CONST robtarget pA:=[[900,0,900],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    MoveJ pA, v500, fine, tool0;
    MoveL pMissing, v500, fine, tool0;
  ENDPROC
ENDMODULE
