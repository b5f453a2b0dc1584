%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%

MODULE DataByName
  ! Visits the teach points p1..p4 by name, as a cell whose HMI
  ! picks the point by its number does.
  CONST robtarget p1:=[[900,-200,500],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget p2:=[[1000,-100,550],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget p3:=[[1050,100,600],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget p4:=[[950,250,650],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  VAR robtarget rtWork;
  VAR robtarget rtAbove;
  VAR num nLift1:=50;
  VAR num nLift2:=70;
  VAR num nZero:=0;
  VAR string sName;
  VAR datapos block;
  VAR num nFound:=0;
  PERS tooldata tGrip:=[TRUE,[[0,0,120],[1,0,0,0]],[1,[0,0,40],[1,0,0,0],0,0,0]];
  PERS tooldata tActive:=[TRUE,[[0,0,1],[1,0,0,0]],[0.1,[0,0,1],[1,0,0,0],0,0,0]];

  PROC main()
    ConfJ\Off;
    ConfL\Off;
    MoveJ Offs(p1,0,0,200),v1000,fine,tool0;
    ! the points by their number
    FOR i FROM 1 TO 4 DO
      GetDataVal "p"+NumToStr(i,0),rtWork;
      MoveL rtWork,v500,fine,tool0;
    ENDFOR
    ! a point written by its name
    rtWork:=Offs(p4,0,0,100);
    SetDataVal "rtAbove",rtWork;
    MoveL rtAbove,v500,fine,tool0;
    ! every robtarget whose name has a p in it
    SetDataSearch "robtarget"\Object:="p.*";
    WHILE GetNextSym(sName,block) DO
      GetDataVal sName\Block:=block,rtWork;
      MoveL rtWork,v500,fine,tool0;
      Incr nFound;
    ENDWHILE
    ! all the lifts at once
    SetAllDataVal "num"\Object:="nLift.*",nZero;
    MoveL Offs(p1,0,0,nLift1+nLift2),v500,fine,tool0;
    ! the active tool
    MoveL p2,v500,fine,tGrip;
    GetSysData tActive;
    MoveL Offs(p3,0,0,tActive.tframe.trans.z),v500,fine,tool0;
    SetSysData tool0;
    GetSysData tActive;
    MoveL Offs(p4,0,0,50+tActive.tframe.trans.z),v500,fine,tool0;
  ENDPROC
ENDMODULE
