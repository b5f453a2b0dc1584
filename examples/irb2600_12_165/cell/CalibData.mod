%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%

MODULE CalibData
  ! The cell's tool, work objects and taught points, as RobotStudio writes them.
  TASK PERS tooldata tVacuum:=[TRUE,[[0,0,180],[1,0,0,0]],[6,[0,0,90],[1,0,0,0],0.05,0.05,0.02]];
  TASK PERS wobjdata wPallet:=[FALSE,TRUE,"",[[650,-450,150],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
  TASK PERS wobjdata wConveyor:=[FALSE,TRUE,"",[[300,650,350],[0.7071068,0,0,0.7071068]],[[0,0,0],[1,0,0,0]]];
  CONST robtarget pPick:=[[0,0,0],[0,0,1,0],[0,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pCorner:=[[100,80,0],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST jointtarget jSafe:=[[0,-10,20,0,50,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
ENDMODULE
