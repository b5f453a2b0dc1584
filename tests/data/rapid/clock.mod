MODULE Clk
  ! A clock around a loop of moves: ClkRead reads the task's time, moves included, so the loop ends.
  VAR clock c;
  VAR num t;
  CONST robtarget pA:=[[900,0,600],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pB:=[[900,300,600],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    MoveJ pA, v1000, fine, tool0;
    ClkReset c;
    ClkStart c;
    WHILE ClkRead(c) < 5 DO
      MoveL pB, v500, fine, tool0;
      MoveL pA, v500, fine, tool0;
    ENDWHILE
    ClkStop c;
    t := ClkRead(c);
    TPWrite "t=" \Num:=t;
  ENDPROC
ENDMODULE
