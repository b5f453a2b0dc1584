MODULE Records
  ! A user record type, its components read and written, and built-in record fields.
  RECORD slot
    num row;
    num col;
    string label;
  ENDRECORD
  ALIAS num count;
  VAR slot sNext := [1, 2, "A1"];
  VAR count nSlots := 0;
  VAR robtarget pGrip := [[900,0,500],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  VAR pos xy;
  PROC main()
    sNext.col := sNext.col + 1;
    sNext.label := sNext.label + "b";
    pGrip.trans.z := pGrip.trans.z + 100;
    pGrip.robconf.cf1 := -1;
    xy := pGrip.trans + [1, 2, 3];
    nSlots := sNext.row * 10 + sNext.col;
  ENDPROC
ENDMODULE
