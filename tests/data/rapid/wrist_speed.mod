MODULE WristSpeed
  ! near_singular.mod's 0.5 m MoveL at v1000: at its middle the wrist is 2 degrees from straight
  ! (q5 = 0), where axis 4 must turn fast: its top speed holds the TCP far below 1000 mm/s there.
  CONST robtarget pLeft:=[[1030,-250,1232],[0.7071068,0,0.7071068,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pRight:=[[1030,250,1232],[0.7071068,0,0.7071068,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    ConfJ \Off;
    ConfL \Off;
    MoveJ pLeft, v500, fine, tool0;
    MoveL pRight, v1000, fine, tool0;
  ENDPROC
ENDMODULE
