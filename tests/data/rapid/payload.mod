MODULE Payload
  ! Loads for the export's payload: a box turned on its axes of moment, a
  ! gripper's tooldata, and a stationary tool whose load is not the robot's.
  PERS loaddata lBox := [8,[50,0,150],[0.7071068,0,0.7071068,0],0.05,0.08,0.1];
  PERS tooldata tGripper := [TRUE,[[0,0,200],[1,0,0,0]],[3,[0,0,80],[1,0,0,0],0.01,0.01,0.005]];
  PERS tooldata tStand := [FALSE,[[900,0,400],[1,0,0,0]],[2,[0,0,50],[1,0,0,0],0,0,0]];
  PERS tooldata tBad := [TRUE,[[0,0,200],[1,0,0,0]],[-3,[0,0,80],[1,0,0,0],0,0,0]];
  CONST num nCount := 3;
ENDMODULE
