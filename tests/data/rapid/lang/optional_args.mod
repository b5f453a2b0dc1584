MODULE OptionalArgs
  ! Optional arguments written without a comma, switches, alternatives, a conditional argument.
  VAR num nSeen := 0;
  VAR num nLift := 0;
  VAR bool bFast := FALSE;
  VAR bool bSlow := FALSE;
  PROC Mark(num n \num lift \switch Fast | switch Slow)
    nSeen := n;
    IF Present(lift) nLift := lift;
    bFast := Present(Fast);
    bSlow := Present(Slow);
  ENDPROC
  PROC Pass(\num lift)
    Mark 2 \lift?lift;
  ENDPROC
  PROC main()
    Mark 1\lift:=40\Fast;
    Pass;
    Pass \lift:=7;
    Mark 3, \Slow;
  ENDPROC
ENDMODULE
