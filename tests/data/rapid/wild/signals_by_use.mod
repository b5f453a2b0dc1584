MODULE Gripper
  ! The signals are the PLC's; the task names them where it sets and
  ! waits on them, and reads them bare where it decides.
  CONST robtarget pHome:=[[900,0,900],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pPick:=[[1000,100,450],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pCheck:=[[850,-200,600],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

  PROC main()
    ConfL\Off;
    MoveJ pHome,v1000,fine,tool0;
    IF diPartReady=1 THEN
      MoveL pPick,v300,fine,tool0;
    ENDIF
    IF diInspect=1 AND doGrip=0 THEN
      MoveL pCheck,v300,fine,tool0;
    ENDIF
    MoveJ pHome,v1000,fine,tool0;
  ENDPROC

  PROC rGrip()
    ! never called from main: its words alone make these names signals
    WaitDI diPartReady,1;
    SetDO doGrip,1;
    IF DInput(diInspect)=1 THEN
      TPWrite "inspect";
    ENDIF
  ENDPROC
ENDMODULE
