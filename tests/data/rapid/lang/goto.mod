MODULE GotoLabels
  ! GOTO and labels: a counted loop, a jump out of an IF, a jump forward.
  VAR num n := 0;
  VAR num nSkipped := 0;
  PROC main()
    lAgain:
    n := n + 1;
    IF n < 4 THEN
      GOTO lAgain;
    ENDIF
    GOTO lEnd;
    nSkipped := 1;
    lEnd:
  ENDPROC
ENDMODULE
