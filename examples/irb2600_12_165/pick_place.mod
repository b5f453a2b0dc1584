%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%

MODULE PickPlace
  ! A pick-and-place cycle for the IRB 2600-12/1.65: a 200 mm gripper picks a part on a table in
  ! front of the robot and places it to the side. Written for rswarp's demo (rswarp program).

  PERS tooldata tGripper:=[TRUE,[[0,0,200],[1,0,0,0]],[3,[0,0,80],[1,0,0,0],0,0,0]];
  TASK PERS wobjdata wTable:=[FALSE,TRUE,"",[[900,-300,400],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];

  CONST jointtarget jHome:=[[0,0,0,0,30,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pPick:=[[100,100,150],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pPlace:=[[300,500,100],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pVia:=[[200,300,450],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  VAR speeddata vApproach:=[150,200,5000,1000];
  VAR num nParts:=0;

  PROC main()
    MoveAbsJ jHome\NoEOffs, v1000, z50, tGripper;
    MoveJ Offs(pPick,0,0,250), v1000, z50, tGripper\WObj:=wTable;
    MoveL pPick, vApproach, fine, tGripper\WObj:=wTable;
    SetDO doGrip, 1;
    WaitTime 0.3;
    MoveL Offs(pPick,0,0,250), v500, z20, tGripper\WObj:=wTable;
    MoveC pVia, Offs(pPlace,0,0,250), v500, z20, tGripper\WObj:=wTable;
    MoveL pPlace, vApproach, fine, tGripper\WObj:=wTable;
    WaitTime 0.3;
    MoveL RelTool(pPlace,0,0,-250\Rz:=45), v500, z50, tGripper\WObj:=wTable;
    IF nParts > 10 THEN
      nParts := 0;
    ENDIF
    MoveAbsJ jHome\NoEOffs, v1000, fine, tGripper;
  ENDPROC
ENDMODULE
