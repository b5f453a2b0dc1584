%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%

MODULE Module1
  CONST robtarget pPick := [[900,0,500],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  VAR num nMode;
  PROC main()
    nMode := diMode;
    IF diSafe = 1 AND diPartReady = 0 THEN
      MoveJ Offs(pPick, 0, 0, 100), v1000, z50, tGripper;
      MoveL pPick, v200, fine, tGripper;
      PulseDO doGrip;
    ENDIF
  ENDPROC
ENDMODULE
