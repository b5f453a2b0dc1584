MODULE PositionerWeld
  ! A seam welded on a part clamped to the positioner's face plate (positioner_cell.toml): the
  ! work object is coordinated with the positioner (ufprog FALSE, ufmec STN1), so its frame turns
  ! with the plate, and the torch keeps the seam's line in it while eax_b turns the plate 90
  ! degrees and eax_a holds it tilted 20 degrees towards the robot.
  PERS tooldata tTorch := [TRUE, [[0, 0, 200], [1, 0, 0, 0]], [3, [0, 0, 90], [1, 0, 0, 0], 0, 0, 0]];
  TASK PERS wobjdata wPart := [FALSE, FALSE, "STN1", [[0, 0, 100], [1, 0, 0, 0]], [[0, 0, 0], [1, 0, 0, 0]]];
  CONST robtarget pApproach := [[-150, 0, 60], [0, 0, 1, 0], [0, 0, 0, 0], [20, 0, 9E9, 9E9, 9E9, 9E9]];
  CONST robtarget pSeamStart := [[-150, 0, 0], [0, 0, 1, 0], [0, 0, 0, 0], [20, 0, 9E9, 9E9, 9E9, 9E9]];
  CONST robtarget pSeamEnd := [[150, 0, 0], [0, 0, 1, 0], [0, 0, 0, 0], [20, 90, 9E9, 9E9, 9E9, 9E9]];
  CONST jointtarget jHome := [[0, 0, 0, 0, 30, 0], [0, 0, 9E9, 9E9, 9E9, 9E9]];

  PROC main()
    ConfJ \Off;
    ConfL \Off;
    MoveAbsJ jHome, v1000, fine, tTorch;
    MoveJ pApproach, v1000, z20, tTorch \WObj:=wPart;
    MoveL pSeamStart, v200, fine, tTorch \WObj:=wPart;
    ! the weld: the plate turns 90 degrees under the torch
    MoveL pSeamEnd, v20, fine, tTorch \WObj:=wPart;
    MoveL Offs(pSeamEnd, 0, 0, 60), v500, fine, tTorch \WObj:=wPart;
    MoveAbsJ jHome, v1000, fine, tTorch;
  ENDPROC
ENDMODULE
