MODULE MainModule
  ! FOR, TEST, DIV and MOD place four visits on a grid; WHILE repeats one; IF skips one; CRobT
  ! and RelTool turn the tool where it stands; ConfL\Off lets that line keep its configuration.
  VAR num nDone := 0;
  VAR robtarget pNow;
  CONST jointtarget jStraight := [[0,0,0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    VAR num row;
    MoveAbsJ jStraight, v500, fine, tool0;
    FOR i FROM 0 TO 3 DO
      row := i DIV nRows;
      TEST i MOD 2
      CASE 0:
        Visit Offs(pBase, 0, row * 100, 0), nDone;
      DEFAULT:
        Visit Offs(pBase, 100, row * 100, 0), nDone \lift:=150;
      ENDTEST
    ENDFOR
    WHILE nDone < 6 DO
      IF nDone <> 5 THEN
        Visit Offs(pBase, 50, 50, 0), nDone;
      ELSE
        nDone := nDone + 1;
      ENDIF
    ENDWHILE
    ConfL \Off;
    pNow := CRobT(\Tool:=tGripper\WObj:=wTable);
    MoveL RelTool(pNow, 0, 0, -50 \Rz:=30), v100, fine, tGripper\WObj:=wTable;
  ENDPROC
ENDMODULE
