MODULE Handlers
  ! ERROR, BACKWARD and UNDO handlers are parsed, not run: their statements leave no trace.
  VAR num nTries := 0;
  VAR num nOk := 0;
  PROC Try()
    nOk := nOk + 1;
  BACKWARD
    nTries := 50;
  ERROR (ERR_DIVZERO, 41001)
    IF ERRNO = ERR_WAIT_MAXTIME THEN
      nTries := nTries + 1;
      RETRY;
    ELSEIF ERRNO = ERR_DIVZERO THEN
      TRYNEXT;
    ENDIF
    RAISE;
  UNDO
    nTries := -1;
  ENDPROC
  PROC main()
    Try;
  ERROR
    nTries := 10;
  ENDPROC
ENDMODULE
