MODULE ZoneSquare
  ! A square of four MoveL, corners blended in z50 (a test swaps them for fine).
  CONST robtarget pC1:=[[1000,-200,700],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pC2:=[[1000,200,700],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pC3:=[[1400,200,700],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pC4:=[[1400,-200,700],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    ConfJ \Off;
    ConfL \Off;
    MoveJ pC1, v1000, fine, tool0;
    MoveL pC2, v500, z50, tool0;
    MoveL pC3, v500, z50, tool0;
    MoveL pC4, v500, z50, tool0;
    MoveL pC1, v500, fine, tool0;
  ENDPROC
ENDMODULE
