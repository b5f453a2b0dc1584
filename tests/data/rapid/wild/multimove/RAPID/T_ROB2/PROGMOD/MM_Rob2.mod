%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%

MODULE MM_Rob2
    PERS tasks all_tasks{2}:=[["T_ROB1"],["T_ROB2"]];
    VAR syncident sync1;
    VAR syncident sync2;
    VAR syncident sync3;
    CONST robtarget pWeld1:=[[1500,100,600],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget pWeld2:=[[1500,-100,600],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

    PROC main()
        ConfL\Off;
        WaitSyncTask sync1,all_tasks;
        SyncMoveOn sync2,all_tasks;
        MoveL pWeld1,v100,z1,tool0\ID:=10;
        MoveL pWeld1,v100,z1,tool0\ID:=20;
        MoveL pWeld2,v100,fine,tool0\ID:=30;
        SyncMoveOff sync3;
    ENDPROC
ENDMODULE
