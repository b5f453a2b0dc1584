%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%

MODULE Service
  ! A first draft of a service routine for the IRB 2600-12/1.65: to reach a bin on the floor
  ! in front of the robot, it folds the arm down. rswarp program shows why the draft cannot run:
  ! the arm swings through the floor and into its own base.

  CONST jointtarget jHome:=[[0,0,0,0,30,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST jointtarget jBin:=[[0,120,60,0,30,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pAbove:=[[1100,0,300],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];

  PROC main()
    MoveAbsJ jHome, v1000, fine, tool0;
    MoveJ pAbove, v500, fine, tool0;
    MoveAbsJ jBin, v500, fine, tool0;
    MoveAbsJ jHome, v1000, fine, tool0;
  ENDPROC
ENDMODULE
