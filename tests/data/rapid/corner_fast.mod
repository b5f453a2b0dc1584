MODULE CornerFast
  ! An 800 mm MoveL across the front at v7000: the axes' limits, not the TCP's speed,
  ! decide how fast it goes.
  PERS tooldata tGripper:=[TRUE,[[0,0,200],[1,0,0,0]],[3,[0,0,80],[1,0,0,0],0,0,0]];
  CONST robtarget pFrom:=[[900,-400,500],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pTo:=[[900,400,500],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    MoveJ pFrom, vmax, fine, tGripper;
    MoveL pTo, v7000, fine, tGripper;
  ENDPROC
ENDMODULE
