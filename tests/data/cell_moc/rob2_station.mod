MODULE Rob2Station
  ! ROB_2 of tests/data/moc/multimove stands at x 3200, y 1500, turned 180 degrees: these targets,
  ! in the world, are 900 mm in front of it; eax_a and eax_b tilt and turn STN1.
  CONST jointtarget jHome := [[0, 0, 0, 0, 30, 0], [0, 0, 9E9, 9E9, 9E9, 9E9]];
  CONST robtarget pAbove := [[2300, 1500, 1000], [0, 0, 1, 0], [0, 0, 0, 0], [30, 90, 9E9, 9E9, 9E9, 9E9]];
  CONST robtarget pDown := [[2300, 1600, 800], [0, 0, 1, 0], [0, 0, 0, 0], [30, 90, 9E9, 9E9, 9E9, 9E9]];
  PROC main()
    ConfL\Off;
    MoveAbsJ jHome, v1000, fine, tool0;
    MoveL pAbove, v500, fine, tool0;
    MoveL pDown, v200, fine, tool0;
  ENDPROC
ENDMODULE
