MODULE Lib
  ! Routines with parameters, a FUNC returning a robtarget, routine data, a field assignment.
  FUNC robtarget Above(robtarget p, num height)
    VAR robtarget q;
    q := p;
    q.trans.z := q.trans.z + height;
    RETURN q;
  ENDFUNC

  PROC Visit(robtarget p, INOUT num count \num lift)
    VAR num h := 100;
    IF Present(lift) h := lift;
    MoveJ Above(p, h), v1000, z50, tGripper\WObj:=wTable;
    MoveL p, v200, fine, tGripper\WObj:=wTable;
    count := count + 1;
    MoveL Above(p, h), v500, z20, tGripper\WObj:=wTable;
  ENDPROC
ENDMODULE
