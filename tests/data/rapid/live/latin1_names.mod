MODULE Latin
  ! a name of ISO 8859-1 letters, saved as the controller saves it
  VAR num varÖlcüm := 3;
  VAR num rPosición;
  PROC main()
    rPosición := varÖlcüm * 2;
  ENDPROC
ENDMODULE
