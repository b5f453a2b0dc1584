MODULE PullHold
  ! The taut rig over a program: a wait, the slide run out 200 mm (its clamps
  ! end 100 mm farther apart than the hose is long), a hold there, and back.
  CONST jointtarget jIn := [[0,9E9,9E9,9E9,9E9,9E9],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST jointtarget jOut := [[200,9E9,9E9,9E9,9E9,9E9],[9E9,9E9,9E9,9E9,9E9,9E9]];

  PROC main()
    MoveAbsJ jIn, v100, fine, tool0;
    WaitTime 0.5;
    MoveAbsJ jOut, v100, fine, tool0;
    WaitTime 1;
    MoveAbsJ jIn, v100, fine, tool0;
  ENDPROC
ENDMODULE
