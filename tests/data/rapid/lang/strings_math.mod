MODULE StringsMath
  ! The functions a program computes with.
  VAR string sMsg;
  VAR num nPart;
  VAR num nFound;
  VAR bool bOk;
  VAR num nVal;
  VAR num nAngle;
  VAR num nRound;
  VAR num nBits;
  PROC main()
    sMsg := "Part " + NumToStr(12.345, 1) + " of " + ValToStr(3);
    nPart := StrLen(StrPart("pallet", 2, 3));
    nFound := StrFind("a,b;c", 1, ";");
    bOk := StrToVal("42.5", nVal);
    nAngle := ATan2(1, 1) + ASin(1) + Sqrt(16) + Abs(-2) + Pow(2, 3);
    nRound := Round(2.4567 \Dec:=2) + Trunc(3.99);
    nBits := BitAnd(12, 10) + BitOr(1, 2);
  ENDPROC
ENDMODULE
