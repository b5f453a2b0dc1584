MODULE TrackState
  ! The robot's state read back on the track cell: CJointT and CRobT carry the carriage's eax_a,
  ! CalcJointT and CalcRobT solve with the base where the target's eax_a puts it.
  PERS tooldata tGripper := [TRUE, [[0, 0, 180], [1, 0, 0, 0]], [6, [0, 0, 80], [1, 0, 0, 0], 0, 0, 0]];
  CONST robtarget pHere := [[2200, -500, 900], [0, 0, 1, 0], [-1, 0, -1, 0], [1500, 9E9, 9E9, 9E9, 9E9, 9E9]];
  CONST robtarget pFar := [[3650, -450, 800], [0, 0, 1, 0], [-1, 0, -1, 0], [3000, 9E9, 9E9, 9E9, 9E9, 9E9]];
  VAR jointtarget jNow;
  VAR jointtarget jFar;
  VAR robtarget pNow;
  VAR robtarget pBack;

  PROC main()
    ConfJ \Off;
    ConfL \Off;
    MoveJ pHere, v1000, fine, tGripper;
    jNow := CJointT();
    pNow := CRobT(\Tool:=tGripper);
    MoveL Offs(pNow, 0, 100, 0), v200, fine, tGripper;
    MoveAbsJ jNow, v500, fine, tGripper;
    jFar := CalcJointT(pFar, tGripper);
    MoveAbsJ jFar, v1000, fine, tGripper;
    pBack := CalcRobT(jNow, tGripper);
    MoveL pBack, v1000, fine, tGripper;
  ENDPROC
ENDMODULE
