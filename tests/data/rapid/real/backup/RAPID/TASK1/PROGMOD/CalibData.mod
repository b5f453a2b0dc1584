%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%

MODULE CalibData
    TASK PERS tooldata tGripper:=[TRUE,[[0,0,200],[1,0,0,0]],[3,[0,0,80],[1,0,0,0],0,0,0]];
    TASK PERS wobjdata wobjTable:=[FALSE,TRUE,"",[[800,-300,300],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
    TASK PERS loaddata loadPart:=[1.5,[0,0,40],[1,0,0,0],0,0,0];
ENDMODULE
