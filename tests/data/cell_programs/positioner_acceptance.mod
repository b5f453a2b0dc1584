MODULE PositionerAcceptance
  ! A seam on a part clamped to the positioner's face plate (examples/cells/positioner_cell.toml):
  ! the work object rides on STN1 (ufprog FALSE), 100 mm above the plate. The plate is held tilted
  ! 20 degrees (eax_a) and turns 90 degrees (eax_b) under the torch while the TCP keeps the seam's
  ! line in the work object.
  PERS tooldata tTorch := [TRUE, [[0, 0, 200], [1, 0, 0, 0]], [3, [0, 0, 90], [1, 0, 0, 0], 0, 0, 0]];
  TASK PERS wobjdata wTable := [FALSE, FALSE, "STN1", [[0, 0, 100], [1, 0, 0, 0]], [[0, 0, 0], [1, 0, 0, 0]]];
  CONST robtarget pAbove := [[-150, 0, 80], [0, 0, 1, 0], [0, 0, 0, 0], [20, 0, 9E9, 9E9, 9E9, 9E9]];
  CONST robtarget pSeamStart := [[-150, 0, 0], [0, 0, 1, 0], [0, 0, 0, 0], [20, 0, 9E9, 9E9, 9E9, 9E9]];
  CONST robtarget pSeamEnd := [[150, 0, 0], [0, 0, 1, 0], [0, 0, 0, 0], [20, 90, 9E9, 9E9, 9E9, 9E9]];
  CONST jointtarget jHome := [[0, 0, 0, 0, 30, 0], [0, 0, 9E9, 9E9, 9E9, 9E9]];

  PROC main()
    ConfJ \Off;
    ConfL \Off;
    MoveAbsJ jHome, v1000, fine, tTorch;
    MoveJ pAbove, v1000, fine, tTorch \WObj:=wTable;
    MoveL pSeamStart, v200, fine, tTorch \WObj:=wTable;
    ! the weld: eax_b turns the plate 90 degrees under the torch
    MoveL pSeamEnd, v50, fine, tTorch \WObj:=wTable;
    MoveL Offs(pSeamEnd, 0, 0, 80), v500, fine, tTorch \WObj:=wTable;
    MoveAbsJ jHome, v1000, fine, tTorch;
  ENDPROC
ENDMODULE
