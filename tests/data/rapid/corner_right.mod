MODULE CornerRight
  ! A right angle: 400 mm along x, then 400 mm along y, the corner pCorner a fly-by
  ! point in z50 at v500, the end a stop point (a test swaps z50 for fine).
  PERS tooldata tGripper:=[TRUE,[[0,0,200],[1,0,0,0]],[3,[0,0,80],[1,0,0,0],0,0,0]];
  CONST robtarget pStart:=[[900,-200,600],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pCorner:=[[1300,-200,600],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pEnd:=[[1300,200,600],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    MoveJ pStart, v1000, fine, tGripper;
    MoveL pCorner, v500, z50, tGripper;
    MoveL pEnd, v500, fine, tGripper;
  ENDPROC
ENDMODULE
