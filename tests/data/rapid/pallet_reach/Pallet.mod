MODULE Pallet
  ! Palletizing: each box is picked from the conveyor and placed on a 3 x 4 grid of the pallet,
  ! row by row, the grid built from pPlace (PalletData.mod) by Offs.
  VAR robtarget pDrop;

  PROC main()
    ConfJ \Off;
    ConfL \Off;
    MoveAbsJ jHome\NoEOffs, v1000, z50, tGripper;
    WHILE TRUE DO
      FOR row FROM 0 TO 2 DO
        FOR col FROM 0 TO 3 DO
          PickBox;
          PlaceBox row, col;
        ENDFOR
      ENDFOR
      WaitDI diPalletEmpty, 1;
    ENDWHILE
  ENDPROC

  PROC PickBox()
    MoveJ Offs(pPick, 0, 0, nApproach), v2000, z50, tGripper;
    MoveL pPick, v500, fine, tGripper;
    SetDO doGrip, 1;
    MoveL Offs(pPick, 0, 0, nApproach), v1000, z50, tGripper;
  ENDPROC

  PROC PlaceBox(num row, num col)
    pDrop := Offs(pPlace, row * nPitchX, col * nPitchY, 0);
    MoveJ RelTool(pDrop, 0, 0, -nApproach), v2000, z50, tGripper\WObj:=wPallet;
    MoveL Offs(pPlace, row * nPitchX, col * nPitchY, 0), v300, fine, tGripper\WObj:=wPallet;
    SetDO doGrip, 0;
    MoveL RelTool(pDrop, 0, 0, -nApproach), v1000, z50, tGripper\WObj:=wPallet;
  ENDPROC
ENDMODULE
