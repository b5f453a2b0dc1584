MODULE Undeclared
  ! The approach height lived in a module that was not copied.
  CONST robtarget pPick:=[[950,0,400],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

  PROC main()
    MoveJ Offs(pPick,0,0,200),v1000,fine,tool0;
    MoveL pPick,v200,fine,tool0;
    MoveL Offs(pPick,0,0,nApproach),v500,fine,tool0;
  ENDPROC
ENDMODULE
