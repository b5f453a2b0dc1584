MODULE Arrays
  ! Arrays of one and two dimensions, elements written in place, passed whole and by element.
  CONST num nRows := 2;
  VAR num grid{nRows, 3} := [[1, 2, 3], [4, 5, 6]];
  VAR num total := 0;
  VAR num dims := 0;
  PROC Bump(INOUT num x)
    x := x + 100;
  ENDPROC
  FUNC num Sum(num a{*,*})
    VAR num s := 0;
    FOR i FROM 1 TO Dim(a, 1) DO
      FOR j FROM 1 TO Dim(a, 2) DO
        s := s + a{i, j};
      ENDFOR
    ENDFOR
    RETURN s;
  ENDFUNC
  PROC main()
    grid{2, 3} := 60;
    Bump grid{1, 1};
    total := Sum(grid);
    dims := Dim(grid, 1) * 10 + Dim(grid, 2);
  ENDPROC
ENDMODULE
