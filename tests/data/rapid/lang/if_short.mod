MODULE IfShort
  ! One-line IF with an assignment, a call and RETURN.
  VAR num n := 5;
  VAR num nCalls := 0;
  VAR bool bDone := TRUE;
  PROC Count()
    Incr nCalls;
  ENDPROC
  PROC Early()
    IF bDone RETURN;
    nCalls := 99;
  ENDPROC
  PROC main()
    IF n > 3 n := 0;
    IF n = 0 Count;
    Early;
  ENDPROC
ENDMODULE
