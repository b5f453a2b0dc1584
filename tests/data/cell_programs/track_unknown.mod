MODULE TrackUnknown
  ! On the track cell: a target that also gives eax_c (an axis the cell does not drive), and a
  ! work object coordinated with STN9, a unit the cell does not have.
  PERS tooldata tGripper := [TRUE, [[0, 0, 180], [1, 0, 0, 0]], [6, [0, 0, 80], [1, 0, 0, 0], 0, 0, 0]];
  TASK PERS wobjdata wStn9 := [FALSE, FALSE, "STN9", [[0, 0, 100], [1, 0, 0, 0]], [[0, 0, 0], [1, 0, 0, 0]]];
  CONST robtarget pWithC := [[1400, -500, 900], [0, 0, 1, 0], [-1, 0, -1, 0], [700, 9E9, 250, 9E9, 9E9, 9E9]];
  CONST robtarget pOnStn9 := [[0, 0, 0], [0, 0, 1, 0], [-1, 0, -1, 0], [700, 9E9, 9E9, 9E9, 9E9, 9E9]];

  PROC main()
    ConfJ \Off;
    ConfL \Off;
    MoveJ pWithC, v1000, fine, tGripper;
    MoveL pOnStn9, v200, fine, tGripper \WObj:=wStn9;
  ENDPROC
ENDMODULE
