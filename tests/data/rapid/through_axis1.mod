MODULE Through
  ! A MoveL whose line passes over axis 1: the wrist centre would cross the J1 axis, which no
  ! configuration can follow.
  CONST robtarget pFront:=[[700,100,1100],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pBack:=[[-700,100,1100],[0,0,1,0],[1,0,1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    MoveJ pFront, v500, fine, tool0;
    MoveL pBack, v200, fine, tool0;
  ENDPROC
ENDMODULE
