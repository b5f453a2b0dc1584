MODULE ZoneSlowNext
  ! A fast move into a zone followed by a slow one (a MoveJ at v1000 in z50, then a MoveL down at
  ! v150): the slow move speeds up over the blend's time, not over the zone's length, so the zone
  ! saves time against fine, as on the controller (a test swaps z50 for fine).
  CONST robtarget pUp:=[[1000,0,900],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pDown:=[[1000,0,700],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pSide:=[[1000,300,900],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    ConfJ \Off;
    ConfL \Off;
    MoveJ pSide, v1000, fine, tool0;
    MoveJ pUp, v1000, z50, tool0;
    MoveL pDown, v150, fine, tool0;
    MoveL pUp, v1000, z50, tool0;
    MoveL pSide, v100, fine, tool0;
  ENDPROC
ENDMODULE
