%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%

MODULE TrackTransfer
  ! A machine-tending transfer along the 4 m track (track_cell.toml): pick at the infeed near the
  ! track's start, carry the part 3 m down the line with the carriage moving under a straight
  ! MoveL, place it at the outfeed. eax_a is the carriage's position on the track in mm.
  PERS tooldata tGripper := [TRUE, [[0, 0, 180], [1, 0, 0, 0]], [6, [0, 0, 80], [1, 0, 0, 0], 0, 0, 0]];
  PERS wobjdata wLine := [FALSE, TRUE, "", [[0, 0, 0], [1, 0, 0, 0]], [[0, 0, 0], [1, 0, 0, 0]]];
  CONST robtarget pInfeedApp := [[900, -600, 900], [0, 0, 1, 0], [-1, 0, -1, 0], [200, 9E9, 9E9, 9E9, 9E9, 9E9]];
  CONST robtarget pInfeed := [[900, -600, 700], [0, 0, 1, 0], [-1, 0, -1, 0], [200, 9E9, 9E9, 9E9, 9E9, 9E9]];
  CONST robtarget pCarry := [[2400, -300, 1000], [0, 0, 1, 0], [-1, 0, -1, 0], [1700, 9E9, 9E9, 9E9, 9E9, 9E9]];
  CONST robtarget pOutfeedApp := [[3900, -600, 900], [0, 0, 1, 0], [-1, 0, -1, 0], [3200, 9E9, 9E9, 9E9, 9E9, 9E9]];
  CONST robtarget pOutfeed := [[3900, -600, 700], [0, 0, 1, 0], [-1, 0, -1, 0], [3200, 9E9, 9E9, 9E9, 9E9, 9E9]];
  VAR robtarget pNow;

  PROC main()
    ConfJ \Off;
    ConfL \Off;
    MoveJ pInfeedApp, v2000, z50, tGripper \WObj:=wLine;
    MoveL pInfeed, v500, fine, tGripper \WObj:=wLine;
    WaitTime 0.3;
    MoveL pInfeedApp, v1000, z50, tGripper \WObj:=wLine;
    MoveL pCarry, v1500, z100, tGripper \WObj:=wLine;
    MoveL pOutfeedApp, v1500, z50, tGripper \WObj:=wLine;
    MoveL pOutfeed, v500, fine, tGripper \WObj:=wLine;
    pNow := CRobT(\Tool:=tGripper \WObj:=wLine);
    WaitTime 0.3;
    MoveL Offs(pNow, 0, 0, 200), v1000, fine, tGripper \WObj:=wLine;
  ENDPROC
ENDMODULE
