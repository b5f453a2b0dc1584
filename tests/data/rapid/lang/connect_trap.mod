MODULE ConnectTrap
  ! An interrupt connected to a TRAP: parsed, never run (its signal never rises).
  VAR intnum iStop;
  VAR num nTrapped := 0;
  TRAP tStop
    nTrapped := nTrapped + 1;
    IDelete iStop;
  ENDTRAP
  PROC main()
    IDelete iStop;
    CONNECT iStop WITH tStop;
    ISignalDI diStop, 1, iStop;
    TPWrite "armed";
  ENDPROC
ENDMODULE
