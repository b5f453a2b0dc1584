%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%

MODULE WristIntoRail
  ! The IRB 2600 on the 4 m track (examples/cells/track_cell.toml), pointing straight down: the
  ! second move puts the flange 60 mm below the floor at the carriage's 800 mm, right over the
  ! rail (the rail's top is 200 mm up), so the wrist goes into the rail; then it comes back up.
  PERS tooldata tShort := [TRUE, [[0, 0, 150], [1, 0, 0, 0]], [2, [0, 0, 50], [1, 0, 0, 0], 0, 0, 0]];
  CONST robtarget pAbove := [[1200, 0, 800], [0, 0, 1, 0], [0, 0, 0, 0], [0, 9E9, 9E9, 9E9, 9E9, 9E9]];
  CONST robtarget pLow := [[1600, 0, -60], [0, 0, 1, 0], [0, 0, 0, 0], [800, 9E9, 9E9, 9E9, 9E9, 9E9]];

  PROC main()
    ConfJ \Off;
    MoveJ pAbove, v1000, fine, tShort;
    MoveJ pLow, v500, fine, tShort;
    MoveJ pAbove, v1000, fine, tShort;
  ENDPROC
ENDMODULE
