%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%

MODULE Module1
    !***********************************************************
    ! Module:  Module1
    ! Description: machine tending. The PLC's inputs come from
    !   the cell's I/O configuration (EIO.cfg).
    !***********************************************************
    CONST jointtarget jHome:=[[0,0,0,0,30,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget pFeed:=[[950,-150,450],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget pChuck:=[[1000,200,700],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget pReject:=[[800,-300,500],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

    PROC main()
        MoveAbsJ jHome\NoEOffs,v1000,fine,tool0;
        IF diStart=1 THEN
            rLoad;
        ENDIF
        IF diReject=1 THEN
            MoveJ Offs(pReject,0,0,100),v1000,z50,tool0;
            MoveL pReject,v300,fine,tool0;
        ENDIF
        MoveAbsJ jHome\NoEOffs,v1000,fine,tool0;
    ENDPROC

    PROC rLoad()
        MoveJ Offs(pFeed,0,0,150),v1000,z50,tool0;
        IF diPartReady=1 MoveL pFeed,v300,fine,tool0;
        PulseDO\PLength:=0.2,doGripClose;
        WaitTime 0.3;
        MoveL Offs(pFeed,0,0,150),v500,z50,tool0;
        MoveJ Offs(pChuck,0,0,150),v1000,z50,tool0;
        MoveL pChuck,v300,fine,tool0;
        SetDO doGripClose,0;
        MoveL Offs(pChuck,0,0,150),v500,fine,tool0;
    ENDPROC
ENDMODULE
