MODULE Scopes
  ! A routine's own data shadows the module's; FOR's variable is its own; IN copies, INOUT refers.
  VAR num x := 1;
  VAR num nSeen := 0;
  VAR num nOuter := 0;
  VAR num i := 77;
  PROC Own()
    VAR num x := 2;
    nSeen := x;
  ENDPROC
  PROC Copy(num a, INOUT num b)
    a := a + 5;
    b := b + 5;
  ENDPROC
  PROC main()
    VAR num y := 10;
    Own;
    FOR i FROM 1 TO 3 DO
      nOuter := nOuter + i;
    ENDFOR
    Copy x, y;
    x := x + y;
  ENDPROC
ENDMODULE
