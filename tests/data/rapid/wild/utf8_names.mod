MODULE Uebergabe
  ! Übergabe an das Förderband: die Größe des Teils hebt den Greifer.
  CONST robtarget pÜbergabe:=[[950,-100,550],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  VAR num größe:=30;
  VAR string sMeldung:="Teil übergeben";

  PROC main()
    ConfL\Off;
    MoveJ Offs(pÜbergabe,0,0,200),v1000,fine,tool0;
    MoveL Offs(pÜbergabe,0,0,größe),v200,fine,tool0;
    TPWrite sMeldung;
  ENDPROC
ENDMODULE
