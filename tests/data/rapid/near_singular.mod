MODULE NearSingular
  ! A 0.5 m MoveL across the front of the robot, the tool along x: at its middle the wrist is
  ! 2 degrees from straight (q5 = 0), where axes 4 and 6 must turn fast.
  CONST robtarget pLeft:=[[1030,-250,1232],[0.7071068,0,0.7071068,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pRight:=[[1030,250,1232],[0.7071068,0,0.7071068,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    ConfJ \Off;
    ConfL \Off;
    MoveJ pLeft, v500, fine, tool0;
    MoveL pRight, v200, fine, tool0;
  ENDPROC
ENDMODULE
