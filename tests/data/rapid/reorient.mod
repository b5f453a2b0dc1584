MODULE Reorient
  ! Moves whose path is shorter than their turn: the TCP moves 0.014 mm while the tool turns
  ! about its z axis (axis 6), so the turn at v_ori decides their time, not v_tcp.
  VAR speeddata vOri30:=[100,30,5000,1000];
  CONST robtarget pA:=[[1000,0,700],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  ! 0.014 mm from pA, turned 10 degrees
  CONST robtarget pB:=[[1000.014,0,700],[0,0.0871557,0.9961947,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  ! 0.014 mm from pB, turned 90 degrees more
  CONST robtarget pC:=[[1000.028,0,700],[0,0.7660444,0.6427876,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    ConfJ \Off;
    ConfL \Off;
    MoveJ pA, v1000, fine, tool0;
    MoveL pB, v100, fine, tool0;
    MoveL pC, vOri30, fine, tool0;
    MoveL pC, v100, fine, tool0;
  ENDPROC
ENDMODULE
