MODULE SpeedV100
  ! A 200 mm MoveL at v100 in front of the robot, far from any singularity: between its ramps the
  ! TCP keeps the programmed 100 mm/s, which holds it (tests/test_speed_report.py).
  CONST robtarget pFrom:=[[1000,-100,700],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pTo:=[[1000,100,700],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    ConfJ \Off;
    ConfL \Off;
    MoveJ pFrom, v1000, fine, tool0;
    MoveL pTo, v100, fine, tool0;
    WaitTime 0.2;
  ENDPROC
ENDMODULE
