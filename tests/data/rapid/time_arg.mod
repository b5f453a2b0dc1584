MODULE TimeArg
  ! \T sets a move's time in place of its speeddata; VelSet's override stretches it, its top
  ! speed still bounds the TCP (RAPID reference: MoveL, VelSet)
  CONST robtarget p:=[[900,0,900],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    MoveJ p, v1000, fine, tool0;
    MoveL Offs(p,0,0,200), v100\T:=1, fine, tool0;
    MoveL p, v100\T:=10, fine, tool0;
    MoveL Offs(p,0,0,200), v100, fine, tool0;
    MoveJ p, v100\T:=3, fine, tool0;
    VelSet 50, 5000;
    MoveL Offs(p,0,0,200), v100\T:=1, fine, tool0;
    MoveC Offs(p,0,100,100), p, v20\T:=1, fine, tool0;
    VelSet 100, 100;
    MoveL Offs(p,0,0,200), v1000\T:=1, fine, tool0;
  ENDPROC
ENDMODULE
