MODULE ErrorHandler
  ! ERROR handlers as the controller runs them: RETRY after fixing the cause, TRYNEXT, RAISE to
  ! the caller's handler, a user error booked with BookErrNo, a handler that only takes some.
  VAR errnum ERR_NOPART := -1;
  VAR num nDiv := 0;
  VAR num nRatio := 0;
  VAR num nRetries := 0;
  VAR num nSkipped := 0;
  VAR num nCaught := 0;
  VAR num nAfter := 0;
  PROC Divide()
    nRatio := 10 / nDiv;
  ERROR
    IF ERRNO = ERR_DIVZERO THEN
      nRetries := nRetries + 1;
      nDiv := 4;
      RETRY;
    ENDIF
  ENDPROC
  PROC Skip()
    nSkipped := 1 / 0;
    nSkipped := 7;
  ERROR (ERR_DIVZERO)
    TRYNEXT;
  ENDPROC
  PROC Pick()
    RAISE ERR_NOPART;
    nAfter := 99;
  ERROR
    RAISE;
  ENDPROC
  PROC main()
    BookErrNo ERR_NOPART;
    Divide;
    Skip;
    Pick;
    nAfter := nAfter + 1;
  ERROR
    IF ERRNO = ERR_NOPART nCaught := nCaught + 1;
    TRYNEXT;
  ENDPROC
ENDMODULE
