%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%

MODULE WristOverRail
  ! As wrist_into_rail.mod, but the second target stays 800 mm up: nothing in the cell is hit.
  PERS tooldata tShort := [TRUE, [[0, 0, 150], [1, 0, 0, 0]], [2, [0, 0, 50], [1, 0, 0, 0], 0, 0, 0]];
  CONST robtarget pAbove := [[1200, 0, 800], [0, 0, 1, 0], [0, 0, 0, 0], [0, 9E9, 9E9, 9E9, 9E9, 9E9]];
  CONST robtarget pLow := [[1600, 0, 800], [0, 0, 1, 0], [0, 0, 0, 0], [800, 9E9, 9E9, 9E9, 9E9, 9E9]];

  PROC main()
    ConfJ \Off;
    MoveJ pAbove, v1000, fine, tShort;
    MoveJ pLow, v500, fine, tShort;
    MoveJ pAbove, v1000, fine, tShort;
  ENDPROC
ENDMODULE
