MODULE StandardCycle
  ! ABB's standard cycle for cycle-time figures: with 1 kg, up 25 mm, across 300 mm, down 25 mm,
  ! and back, again and again. Fine at the pick and the place, the upper corners blended in z10,
  ! at the robot's top TCP speed. Centred where the arm reaches with axes 2 and 3 at 20 deg and
  ! the tool pointing down, so the same module runs on every 6-axis arm (rswarp demo, bench_cycle).
  PERS tooldata tLoad1kg:=[TRUE,[[0,0,0],[1,0,0,0]],[1,[0,0,1],[1,0,0,0],0,0,0]];
  CONST jointtarget jCentre:=[[0,20,20,0,50,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  VAR robtarget pCentre;
  VAR robtarget pPick;
  VAR robtarget pPlace;
  PROC main()
    ConfL \Off;
    pCentre := CalcRobT(jCentre, tLoad1kg);
    pPick := Offs(pCentre, 0, -150, 0);
    pPlace := Offs(pCentre, 0, 150, 0);
    MoveL pPick, vmax, fine, tLoad1kg;
    WHILE TRUE DO
      MoveL Offs(pPick, 0, 0, 25), vmax, z10, tLoad1kg;
      MoveL Offs(pPlace, 0, 0, 25), vmax, z10, tLoad1kg;
      MoveL pPlace, vmax, fine, tLoad1kg;
      MoveL Offs(pPlace, 0, 0, 25), vmax, z10, tLoad1kg;
      MoveL Offs(pPick, 0, 0, 25), vmax, z10, tLoad1kg;
      MoveL pPick, vmax, fine, tLoad1kg;
    ENDWHILE
  ENDPROC
ENDMODULE
