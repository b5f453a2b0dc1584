MODULE DataByName
  CONST robtarget p1 := [[900,-200,600],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget p2 := [[900,0,600],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget p3 := [[900,200,600],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  VAR robtarget pTemp;
  VAR num nSpeed := 100;
  VAR num nFound := 0;
  VAR string name;
  VAR datapos block;
  PROC main()
    FOR i FROM 1 TO 3 DO
      GetDataVal "p" + NumToStr(i, 0), pTemp;
      MoveL pTemp, v500, fine, tool0;
    ENDFOR
    SetDataVal "nSpeed", 250;
    SetDataSearch "robtarget" \Object:="p[0-9]";
    WHILE GetNextSym(name, block) DO
      Incr nFound;
    ENDWHILE
    GetDataVal "pNone", pTemp;
  ERROR
    IF ERRNO = ERR_SYM_ACCESS THEN
      TRYNEXT;
    ENDIF
  ENDPROC
ENDMODULE
