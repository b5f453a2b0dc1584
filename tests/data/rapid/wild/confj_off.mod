MODULE ConfJOff
  ! ConfJ\Off: the robot takes the solution it reaches soonest, never a flip over the top
  PERS tooldata tVac:=[TRUE,[[0,0,150],[1,0,0,0]],[1.5,[0,0,60],[1,0,0,0],0,0,0]];
  PERS wobjdata wConv:=[FALSE,TRUE,"",[[800,-400,300],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
  CONST robtarget pDrop:=[[200,900,400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  VAR robtarget pPick;
  PROC main()
    ConfJ\Off;
    MoveJ pDrop, v2000, fine, tVac;
    pPick := [[250,-120,100],OrientZYX(-45,0,180),[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    MoveJ pPick, v2000, fine, tVac\WObj:=wConv;
  ENDPROC
ENDMODULE
