%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%

MODULE MM_Rob1
    ! Robot 1 of a two-robot cell: carries the part while
    ! robot 2 welds it (coordinated, MultiMove).
    PERS tasks all_tasks{2}:=[["T_ROB1"],["T_ROB2"]];
    VAR syncident sync1;
    VAR syncident sync2;
    VAR syncident sync3;
    CONST robtarget pHome:=[[900,0,1000],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget p10:=[[1000,-200,600],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget p20:=[[1000,0,600],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget p30:=[[1000,200,600],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

    PROC main()
        ConfL\Off;
        MoveJ pHome,v1000,fine,tool0;
        WaitSyncTask sync1,all_tasks;
        SyncMoveOn sync2,all_tasks;
        MoveL p10,v500,z10,tool0\ID:=10;
        MoveL p20,v500,z10,tool0\ID:=20;
        MoveL p30,v500,fine,tool0\ID:=30;
        SyncMoveOff sync3;
        MoveJ pHome,v1000,fine,tool0;
    ENDPROC
ENDMODULE
