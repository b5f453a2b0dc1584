MODULE Skipped
  VAR num n:=0;
  CONST robtarget pA:=[[900,0,900],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    MoveJ pA, v500, fine, tool0;
    SetDO do1, 1;
    IF n > 2 THEN
      n := 0;
    ENDIF
    FOR i FROM 1 TO 3 DO
      MoveL pA, v100, fine, tool0;
    ENDFOR
    WaitTime 0.5;
  ENDPROC
ENDMODULE
