%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%

MODULE First
  LOCAL VAR num nOwn := 1;
  VAR num nShared := 10;
  PROC main()
    nShared := nShared + nOwn + Helper();
  ENDPROC
ENDMODULE

MODULE Second(SYSMODULE, NOSTEPIN)
  LOCAL VAR num nOwn := 100;
  FUNC num Helper()
    RETURN nOwn;
  ENDFUNC
ENDMODULE
