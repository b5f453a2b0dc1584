%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%

MODULE TrackAcceptance
  ! The IRB 2600-12/1.65 on the 4 m track (examples/cells/track_cell.toml): targets from 0.9 m to
  ! 3.9 m down the line, far past the arm's own reach; eax_a puts the carriage under each so the
  ! target is about 0.7 m in front of the robot's base. One MoveL carries the part 1.5 m while the
  ! carriage runs under it; one move ends in a zone.
  PERS tooldata tGripper := [TRUE, [[0, 0, 180], [1, 0, 0, 0]], [6, [0, 0, 80], [1, 0, 0, 0], 0, 0, 0]];
  CONST robtarget pPickApp := [[900, -600, 900], [0, 0, 1, 0], [-1, 0, -1, 0], [200, 9E9, 9E9, 9E9, 9E9, 9E9]];
  CONST robtarget pPick := [[900, -600, 700], [0, 0, 1, 0], [-1, 0, -1, 0], [200, 9E9, 9E9, 9E9, 9E9, 9E9]];
  CONST robtarget pCarry := [[2400, -300, 1000], [0, 0, 1, 0], [-1, 0, -1, 0], [1700, 9E9, 9E9, 9E9, 9E9, 9E9]];
  CONST robtarget pPlaceApp := [[3900, -600, 900], [0, 0, 1, 0], [-1, 0, -1, 0], [3200, 9E9, 9E9, 9E9, 9E9, 9E9]];
  CONST robtarget pPlace := [[3900, -600, 700], [0, 0, 1, 0], [-1, 0, -1, 0], [3200, 9E9, 9E9, 9E9, 9E9, 9E9]];

  PROC main()
    ConfJ \Off;
    ConfL \Off;
    MoveJ pPickApp, v1000, fine, tGripper;
    MoveL pPick, v500, fine, tGripper;
    MoveL pPickApp, v500, fine, tGripper;
    ! the carry: the TCP goes 1.5 m along its line while the carriage runs 1500 mm under it
    MoveL pCarry, v1000, fine, tGripper;
    MoveL pPlaceApp, v1000, z50, tGripper;
    MoveL pPlace, v500, fine, tGripper;
    MoveJ pPickApp, v2000, fine, tGripper;
  ENDPROC
ENDMODULE
