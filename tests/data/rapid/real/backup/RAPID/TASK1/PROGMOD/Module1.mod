%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%

MODULE Module1
    !***********************************************************
    ! Module:  Module1
    ! Description: picks three parts from the infeed table and
    !   stacks them at the outfeed. Tools and work objects are
    !   in CalibData.
    ! Author: cell integrator
    ! Version: 1.2
    !***********************************************************
    CONST jointtarget jHome:=[[0,0,0,0,30,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget pPick:=[[100,100,50],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget pPlace:=[[300,450,80],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    PERS num nPartsDone:=0;
    VAR num nCycleTime:=0;

    PROC main()
        Init;
        FOR i FROM 1 TO 3 DO
            PickPart pPick, i;
            PlacePart pPlace, i, 60;
        ENDFOR
        MoveAbsJ jHome\NoEOffs, v1000, fine, tGripper;
        ClkStop clock1;
        nCycleTime := ClkRead(clock1);
        TPWrite "Cycle time: "\Num:=nCycleTime;
    ENDPROC

    PROC Init()
        AccSet 70, 70;
        ClkReset clock1;
        ClkStart clock1;
        reg1 := 0;
        GripLoad load0;
        MoveAbsJ jHome\NoEOffs, v1000, z50, tool0;
    ENDPROC

    PROC PickPart(robtarget pTarget, num nIndex)
        VAR robtarget pApp;
        pApp := Offs(pTarget, (nIndex - 1) * 50, 0, 150);
        MoveJ pApp, v1000, z50, tGripper\WObj:=wobjTable;
        MoveL Offs(pApp, 0, 0, -150), v200, fine, tGripper\WObj:=wobjTable;
        SetDO doGripper, 1;
        WaitTime 0.2;
        GripLoad loadPart;
        MoveL pApp, v500, z20, tGripper\WObj:=wobjTable;
    ENDPROC

    PROC PlacePart(robtarget pTarget, num nIndex, num nStack)
        VAR robtarget p;
        p := pTarget;
        p.trans.z := p.trans.z + (nIndex - 1) * nStack;
        MoveJ Offs(p, 0, 0, 100), v1000, z50, tGripper\WObj:=wobjTable;
        MoveL p, v200, fine, tGripper\WObj:=wobjTable;
        SetDO doGripper, 0;
        WaitTime 0.2;
        GripLoad load0;
        MoveL Offs(p, 0, 0, 100), v500, z20, tGripper\WObj:=wobjTable;
        Incr nPartsDone;
        reg1 := reg1 + 1;
    ENDPROC
ENDMODULE
