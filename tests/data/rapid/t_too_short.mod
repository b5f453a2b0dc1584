MODULE TTooShort
  ! \T shorter than the axes can go (0.1 s for 600 mm): the move takes what the axes need, with
  ! a warning at its line; a \T the axes can keep (5 s) is kept.
  CONST robtarget pA:=[[1000,-300,700],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pB:=[[1000,300,700],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    ConfL \Off;
    ConfJ \Off;
    MoveJ pA, v1000, fine, tool0;
    MoveL pB, v1000\T:=0.1, fine, tool0;
    MoveL pA, v1000\T:=5, fine, tool0;
  ENDPROC
ENDMODULE
