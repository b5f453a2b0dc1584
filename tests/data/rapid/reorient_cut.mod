MODULE ReorientCut
  ! Axis 5 at 118.5 degrees, 1.5 from its limit, and a MoveL 0.014 mm long that turns the tool
  ! 179 degrees about its y axis: the path is probed every 0.02 rad of turn and axis 5 leaves its
  ! limit at the second probe, so the move stops there. Cut to two probes, it once took 6.4e9 s.
  CONST jointtarget jNear:=[[0,0,0,0,118.5,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pTurned:=[[904.4555,0,1185.3005],[-0.9713421,0,-0.2376859,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    ConfJ \Off;
    ConfL \Off;
    MoveAbsJ jNear, v1000, fine, tool0;
    MoveL pTurned, v100, fine, tool0;
  ENDPROC
ENDMODULE
