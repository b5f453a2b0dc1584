MODULE DivMod
  ! Grid index arithmetic: DIV and MOD truncate toward zero, as the controller does.
  VAR num nRow;
  VAR num nCol;
  VAR num nNeg;
  VAR num nRem;
  VAR num nMix;
  PROC main()
    nRow := 14 DIV 4;
    nCol := 14 MOD 4;
    nNeg := -14 DIV 4;
    nRem := -14 MOD 4;
    nMix := 2 + 3 * 4 - 10 / 4 + 7 MOD 3;
  ENDPROC
ENDMODULE
