MODULE QuadrantEdge
  ! Axis 1 at 0 exactly, in a work object turned a quarter turn as RobotStudio writes it (7
  ! digits): the pose CRobT reads solves to q1 = -1e-12 as often as to 0, and cf1 = 0 must hold.
  PERS tooldata tGun:=[TRUE,[[0,50,200],[0.9659258,0,0.258819,0]],[1.5,[0,0,80],[1,0,0,0],0,0,0]];
  TASK PERS wobjdata wFix:=[FALSE,TRUE,"",[[1000,300,600],[0.7071068,0,0,0.7071068]],[[0,0,0],[1,0,0,0]]];
  CONST robtarget pFront:=[[-300,0,200],[0,0,1,0],[0,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  VAR robtarget p;
  PROC main()
    MoveAbsJ [[0,0,0,0,30,0],[9E9,9E9,9E9,9E9,9E9,9E9]]\NoEOffs, v1000, fine, tGun;
    p := CRobT(\Tool:=tGun\WObj:=wFix);
    MoveL p, v500, fine, tGun\WObj:=wFix;
    MoveJ pFront, v1000, fine, tool0\WObj:=wFix;
  ENDPROC
ENDMODULE
