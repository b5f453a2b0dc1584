%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%

MODULE Monitor
    ! Semi-static background task: mirrors the cell state to the PLC.
    VAR num nHeartbeat := 0;
    VAR bool bFault := FALSE;

    PROC main()
        WHILE TRUE DO
            IF DInput(diStart) = 1 AND NOT bFault THEN
                SetDO doRunning, 1;
            ELSE
                SetDO doRunning, 0;
            ENDIF
            bFault := DInput(diEStop) = 0;
            nHeartbeat := (nHeartbeat + 1) MOD 100;
            SetGO goHeartbeat, nHeartbeat;
            WaitTime 0.1;
        ENDWHILE
    ENDPROC
ENDMODULE
