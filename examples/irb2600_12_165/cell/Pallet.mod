MODULE Pallet
  ! Where a box goes: the pallet pattern as a record, the slot of box k by DIV and MOD.
  RECORD pattern
    num cols;
    num rows;
    num layers;
    num dx;
    num dy;
    num dz;
  ENDRECORD

  PERS pattern patBoxes:=[3,2,2,160,140,120];

  FUNC robtarget Slot(num k)
    VAR num perLayer;
    VAR num layer;
    VAR num n;
    perLayer := patBoxes.cols * patBoxes.rows;
    layer := k DIV perLayer;
    n := k MOD perLayer;
    RETURN Offs(pCorner, (n MOD patBoxes.cols) * patBoxes.dx, (n DIV patBoxes.cols) * patBoxes.dy,
                layer * patBoxes.dz);
  ENDFUNC

  PROC Place(robtarget p, INOUT num count)
    VAR robtarget pAbove;
    pAbove := RelTool(p, 0, 0, -250);
    MoveJ pAbove, v2000, z100, tVacuum\WObj:=wPallet;
    MoveL p, v500, fine, tVacuum\WObj:=wPallet;
    SetDO doVacuum, 0;
    WaitTime 0.2;
    MoveL pAbove, v1000, z50, tVacuum\WObj:=wPallet;
    count := count + 1;
  ENDPROC
ENDMODULE
