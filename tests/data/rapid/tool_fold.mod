MODULE ToolFold
  ! A 300 mm gripper on the flange: its TCP at the tip (tGrip), a tooldata
  ! measured wrong by 250 mm (tWrong), and a fold of axis 5 that swings the
  ! gripper into the upper arm.
  PERS tooldata tGrip := [TRUE,[[0,0,300],[1,0,0,0]],[4.5,[0,0,120],[1,0,0,0],0,0,0]];
  PERS tooldata tWrong := [TRUE,[[0,0,550],[1,0,0,0]],[4.5,[0,0,120],[1,0,0,0],0,0,0]];
  CONST jointtarget jStart := [[0,0,0,0,30,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST jointtarget jFold := [[0,0,0,0,120,0],[9E9,9E9,9E9,9E9,9E9,9E9]];

  PROC main()
    MoveAbsJ jStart, v500, fine, tGrip;
    MoveAbsJ jFold, v500, fine, tGrip;
    MoveAbsJ jStart, v500, fine, tWrong;
  ENDPROC
ENDMODULE
