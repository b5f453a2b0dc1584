%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%

MODULE CellLog
  ! Logs each cycle to a file and to the error log; the gripper is
  ! a PickMaster tool whose option module is not in this copy.
  VAR iodev logfile;
  VAR rawbytes raw;
  VAR num nVal:=0;
  VAR num nParts:=0;
  VAR intnum irFault;
  CONST robtarget pA:=[[950,-100,600],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  CONST robtarget pB:=[[1000,150,500],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

  PROC main()
    ConfL\Off;
    MoveJ pA,v1000,fine,tool0;
    Open "HOME:"\File:="cycle.log",logfile\Append;
    Write logfile,"cycle start";
    Close logfile;
    RenameFile "HOME:/cycle.log","HOME:/cycle_old.log";
    ClearRawBytes raw;
    PackRawBytes 12.5,raw,1\Float4;
    UnpackRawBytes raw,1,nVal\Float4;
    ErrLog 4800,"CellLog","cycle started","","","";
    TPWrite "Cycle started";
    IError COMMON_ERR,TYPE_ALL,irFault;
    CellGripAction "Grip";
    nParts:=PmGetPartCount(1);
    MoveL pB,v500,fine,tool0;
    CellGripAction "Release";
    MoveL pA,v500,fine,tool0;
  ENDPROC
ENDMODULE
