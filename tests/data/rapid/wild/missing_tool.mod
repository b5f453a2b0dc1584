%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%

MODULE MainModule
  ! tSuction is calibrated on the controller (CalibData.mod), not in this copy.
  CONST robtarget pPick:=[[950,0,400],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

  PROC main()
    MoveJ Offs(pPick,0,0,200),v1000,fine,tool0;
    MoveL pPick,v200,fine,tSuction;
  ENDPROC
ENDMODULE
