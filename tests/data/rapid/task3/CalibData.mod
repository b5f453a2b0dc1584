MODULE CalibData
  ! The cell's tool, work object and taught point: used by the other modules.
  TASK PERS tooldata tGripper:=[TRUE,[[0,0,200],[1,0,0,0]],[3,[0,0,80],[1,0,0,0],0,0,0]];
  TASK PERS wobjdata wTable:=[FALSE,TRUE,"",[[900,-300,400],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
  CONST robtarget pBase:=[[100,100,150],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PERS num nRows:=2;
ENDMODULE
