%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%

MODULE Seam1
    ! ROB_1 of a two-robot weld cell (MultiMove): it welds the near seam of the fixture while
    ! ROB_2, facing it across the fixture, welds the far one; both start and end together.
    PERS tasks all_tasks{2}:=[["T_ROB1"],["T_ROB2"]];
    VAR syncident sync_ready;
    VAR syncident sync_on;
    VAR syncident sync_off;
    VAR syncident sync_clear;
    CONST robtarget pHome:=[[900,0,1000],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget pSeam1:=[[1000,-200,600],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget pSeam2:=[[1000,0,600],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget pSeam3:=[[1000,200,600],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

    PROC main()
        ConfL\Off;
        MoveJ pHome,v1000,fine,tool0;
        MoveJ Offs(pSeam1,0,0,100),v1000,z20,tool0;
        WaitSyncTask sync_ready,all_tasks;
        SyncMoveOn sync_on,all_tasks;
        MoveL pSeam1,v200,fine,tool0\ID:=10;
        MoveL pSeam2,v50,z1,tool0\ID:=20;
        MoveL pSeam3,v50,fine,tool0\ID:=30;
        MoveL Offs(pSeam3,0,0,100),v500,fine,tool0\ID:=40;
        SyncMoveOff sync_off;
        MoveJ pHome,v1000,fine,tool0;
        WaitSyncTask sync_clear,all_tasks;
    ENDPROC
ENDMODULE
