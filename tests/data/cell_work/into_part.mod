MODULE IntoPart
  ! The torch's flange driven down into the work piece on the face plate while the plate turns.
  PERS tooldata tShort := [TRUE, [[0, 0, 10], [1, 0, 0, 0]], [1, [0, 0, 5], [1, 0, 0, 0], 0, 0, 0]];
  TASK PERS wobjdata wPart := [FALSE, FALSE, "STN1", [[0, 0, 100], [1, 0, 0, 0]], [[0, 0, 0], [1, 0, 0, 0]]];
  CONST robtarget pAbove := [[0, 0, 300], [0, 0, 1, 0], [0, 0, 0, 0], [0, 0, 9E9, 9E9, 9E9, 9E9]];
  CONST robtarget pIn := [[0, 0, -20], [0, 0, 1, 0], [0, 0, 0, 0], [0, 45, 9E9, 9E9, 9E9, 9E9]];
  PROC main()
    ConfJ \Off;
    ConfL \Off;
    MoveJ pAbove, v1000, fine, tShort \WObj:=wPart;
    MoveL pIn, v200, fine, tShort \WObj:=wPart;
    MoveL pAbove, v200, fine, tShort \WObj:=wPart;
  ENDPROC
ENDMODULE
