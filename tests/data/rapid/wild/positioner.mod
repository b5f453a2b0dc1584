MODULE Positioner
  ! The part sits on a two-axis positioner (STN1): its work object
  ! moves with the positioner's axes.
  PERS wobjdata wobjStn1:=[FALSE,FALSE,"STN1",[[0,0,0],[1,0,0,0]],[[0,0,250],[1,0,0,0]]];
  CONST robtarget pSeam:=[[50,0,0],[0,0,1,0],[0,0,0,0],[0,0,9E+09,9E+09,9E+09,9E+09]];

  PROC main()
    MoveJ pSeam,v500,fine,tool0\WObj:=wobjStn1;
  ENDPROC
ENDMODULE
