%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%

MODULE Medicion
  ! Medición de la pieza: posición de referencia y altura en mm.
  ! Ölçüm: ölçülen yükseklik
  CONST robtarget rPosición:=[[1000,100,500],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  VAR num varÖlcüm:=50;
  VAR num nAltura:=0;

  PROC main()
    MoveJ Offs(rPosición,0,0,200),v1000,fine,tool0;
    nAltura:=varÖlcüm*2;
    MoveL Offs(rPosición,0,0,nAltura),v200,fine,tool0;
    TPWrite "Posición alcanzada";
  ENDPROC
ENDMODULE
