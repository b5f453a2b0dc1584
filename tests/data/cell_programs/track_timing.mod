MODULE TrackTiming
  ! Joint moves on the track cell: one that runs the carriage 2000 mm with the arm's joints held,
  ! and one that moves the arm and the carriage together.
  PERS tooldata tGripper := [TRUE, [[0, 0, 180], [1, 0, 0, 0]], [6, [0, 0, 80], [1, 0, 0, 0], 0, 0, 0]];
  CONST jointtarget jAt0 := [[0, -10, 20, 0, 60, 0], [0, 9E9, 9E9, 9E9, 9E9, 9E9]];
  CONST jointtarget jAt2000 := [[0, -10, 20, 0, 60, 0], [2000, 9E9, 9E9, 9E9, 9E9, 9E9]];
  CONST robtarget pDown := [[3300, -500, 800], [0, 0, 1, 0], [-1, 0, -1, 0], [2600, 9E9, 9E9, 9E9, 9E9, 9E9]];

  PROC main()
    ConfJ \Off;
    ConfL \Off;
    MoveAbsJ jAt0, v5000, fine, tGripper;
    ! the carriage alone: 2 m down the track, the arm still
    MoveAbsJ jAt2000, v5000, fine, tGripper;
    ! the arm and the carriage together
    MoveJ pDown, v5000, fine, tGripper;
  ENDPROC
ENDMODULE
