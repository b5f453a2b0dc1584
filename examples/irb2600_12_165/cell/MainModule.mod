MODULE MainModule
  ! A palletizing cycle for the IRB 2600-12/1.65: wait for the PLC's start, pick each box from
  ! the conveyor, stack it on the pallet (Pallet.mod), then retract straight up from wherever the
  ! last box left the tool (CRobT). The cell's data is in CalibData.mod.
  VAR num nBoxes := 0;
  VAR robtarget pNow;

  PROC main()
    MoveAbsJ jSafe\NoEOffs, v1000, z50, tVacuum;
    WHILE TRUE DO
      WaitDI diPalletReady, 1;
      FOR k FROM 0 TO patBoxes.cols * patBoxes.rows * patBoxes.layers - 1 DO
        Pick;
        Place Slot(k), nBoxes;
      ENDFOR
      pNow := CRobT(\Tool:=tVacuum\WObj:=wPallet);
      pNow.trans.z := pNow.trans.z + 300;
      MoveL pNow, v1000, fine, tVacuum\WObj:=wPallet;
      MoveAbsJ jSafe\NoEOffs, v1000, fine, tVacuum;
    ENDWHILE
  ENDPROC

  PROC Pick()
    MoveJ Offs(pPick, 0, 0, 200), v2000, z100, tVacuum\WObj:=wConveyor;
    MoveL pPick, v800, fine, tVacuum\WObj:=wConveyor;
    SetDO doVacuum, 1;
    WaitTime 0.15;
    MoveL Offs(pPick, 0, 0, 200), v1000, z50, tVacuum\WObj:=wConveyor;
  ENDPROC
ENDMODULE
