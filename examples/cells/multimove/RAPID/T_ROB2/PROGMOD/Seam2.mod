%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%

MODULE Seam2
    ! ROB_2 of the two-robot weld cell: 2.6 m across the fixture from ROB_1, turned to face it
    ! (SYSPAR/MOC.cfg); its targets are in the world frame, as wobj0 is on a MultiMove system.
    PERS tasks all_tasks{2}:=[["T_ROB1"],["T_ROB2"]];
    VAR syncident sync_ready;
    VAR syncident sync_on;
    VAR syncident sync_off;
    VAR syncident sync_clear;
    CONST robtarget pHome2:=[[1700,0,1000],[0,1,0,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget pWeld1:=[[1500,200,600],[0,1,0,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget pWeld2:=[[1500,0,600],[0,1,0,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget pWeld3:=[[1500,-200,600],[0,1,0,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

    PROC main()
        ConfJ\Off;
        ConfL\Off;
        MoveJ pHome2,v1000,fine,tool0;
        MoveJ Offs(pWeld1,0,0,100),v1000,z20,tool0;
        WaitSyncTask sync_ready,all_tasks;
        SyncMoveOn sync_on,all_tasks;
        MoveL pWeld1,v200,fine,tool0\ID:=10;
        MoveL pWeld2,v40,z1,tool0\ID:=20;
        MoveL pWeld3,v40,fine,tool0\ID:=30;
        MoveL Offs(pWeld3,0,0,100),v500,fine,tool0\ID:=40;
        SyncMoveOff sync_off;
        MoveJ pHome2,v1000,fine,tool0;
        WaitSyncTask sync_clear,all_tasks;
    ENDPROC
ENDMODULE
