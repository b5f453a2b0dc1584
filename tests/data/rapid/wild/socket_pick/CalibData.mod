%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%

MODULE CalibData
    ! Tool of the vacuum gripper, measured with the 4-point method
    TASK PERS tooldata tVac:=[TRUE,[[0,0,150],[1,0,0,0]],[2.5,[0,0,60],[1,0,0,0],0,0,0]];
ENDMODULE
