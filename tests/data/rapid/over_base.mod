MODULE OverBase
  ! Machine tending: each part is carried from the lathe in front of the robot to the outfeed
  ! behind it by one MoveL straight over the robot's base, which no configuration can follow.
  CONST robtarget pLathe:=[[700,100,1100],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pOutfeed:=[[-700,100,1100],[0,0,1,0],[1,0,1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pDeep:=[[350,0,400],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];

  PROC main()
    ConfL \Off;
    WHILE TRUE DO
      FOR part FROM 1 TO 2 DO
        MoveJ pLathe, v1000, fine, tool0;
        MoveL pOutfeed, v500, fine, tool0;
      ENDFOR
      MoveJ pDeep, v1000, fine, tool0;
    ENDWHILE
  ENDPROC
ENDMODULE
