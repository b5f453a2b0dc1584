MODULE StringsVectors
  ! RAPID's string and vector functions, as the reference manual defines them
  VAR string sPos; VAR string sThird; VAR string sRound; VAR string sNeg; VAR string sBig;
  VAR pos p := [100, 250.5, 0];
  VAR pos c1; VAR pos c2;
  VAR pos q; VAR num n; VAR bool b;
  VAR bool okPos; VAR bool okNum; VAR bool okBool; VAR bool okBad;
  VAR num at; VAR num atNone; VAR string sMapped;
  VAR num grid{2,3} := [[1,2,3],[4,5,6]];
  VAR num cube{2,2,2} := [[[1,2],[3,4]],[[5,6],[7,8]]];
  VAR num nGrid; VAR num nCube;
  PROC main()
    sPos := ValToStr(p);
    sThird := ValToStr(1/3);
    sRound := NumToStr(0.3125, 3);
    sNeg := NumToStr(-2.5, 0);
    sBig := ValToStr(1234567);
    c1 := [1,0,0] * p;
    c2 := CrossProd([0,1,0], [0,0,1]);
    okPos := StrToVal("[600,500,225.3]", q);
    okNum := StrToVal("3.85", n);
    okBool := StrToVal("TRUE", b);
    okBad := StrToVal("12a", n);
    at := StrMatch("robot,45,60", 1, ",60");
    atNone := StrMatch("robot", 1, "x");
    sMapped := StrMap("abc", "ab", "XY");
    grid := [[0,0,2],[1,0,0]];
    nGrid := grid{1,3} + 10 * grid{2,1};
    nCube := cube{2,1,2};
  ENDPROC
ENDMODULE
