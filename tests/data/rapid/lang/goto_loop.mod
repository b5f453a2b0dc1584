MODULE GotoLoop
  ! An old-style main loop: a label and an unconditional GOTO back to it.
  CONST robtarget pA := [[900,0,600],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pB := [[900,300,600],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    lStart:
    MoveJ pA, v1000, fine, tool0;
    MoveJ pB, v1000, fine, tool0;
    GOTO lStart;
  ENDPROC
ENDMODULE
