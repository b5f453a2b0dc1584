MODULE J1Swing
  ! Axis 1 over 170 degrees, at the robot's top speed: the time is the axis's own.
  CONST jointtarget jRight:=[[-85,0,0,0,30,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST jointtarget jLeft:=[[85,0,0,0,30,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    MoveAbsJ jRight, vmax, fine, tool0;
    MoveAbsJ jLeft, vmax, fine, tool0;
  ENDPROC
ENDMODULE
