MODULE SpeedTools
  ! The TCP's speed is relative to the move's work object: a 200 mm MoveL at v200 that turns 30 deg,
  ! a long tilted tool in a shifted, turned work object; then a 100 mm MoveL at v100, as turning,
  ! with a stationary tool, the robot holding the work object past its TCP (test_speed_report.py).
  PERS tooldata tTilted:=[TRUE,[[50,0,200],[0.9659258,0,0.258819,0]],[1,[0,0,50],[1,0,0,0],0,0,0]];
  PERS wobjdata wTurned:=[FALSE,TRUE,"",[[800,-200,400],[0.9238795,0,0,0.3826834]],[[0,0,50],[1,0,0,0]]];
  PERS tooldata tFixed:=[FALSE,[[1300,0,700],[0,0,1,0]],[1,[0,0,0],[1,0,0,0],0,0,0]];
  PERS wobjdata wHeld:=[TRUE,TRUE,"",[[0,0,100],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
  CONST robtarget pA:=[[100,0,200],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pB:=[[300,0,200],[0,0.258819,0.9659258,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pS1:=[[0,-50,-200],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pS2:=[[0,50,-200],[0.9659258,0,0,0.258819],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    ConfJ \Off;
    ConfL \Off;
    MoveJ pA, v1000, fine, tTilted\WObj:=wTurned;
    MoveL pB, v200, fine, tTilted\WObj:=wTurned;
    MoveJ pS1, v1000, fine, tFixed\WObj:=wHeld;
    MoveL pS2, v100, fine, tFixed\WObj:=wHeld;
  ENDPROC
ENDMODULE
