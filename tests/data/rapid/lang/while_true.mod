MODULE WhileTrue
  ! The usual main loop: WHILE TRUE around a cycle, a wait for a start signal, a polling loop.
  CONST robtarget pA := [[900,0,600],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pB := [[900,300,600],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  VAR num nCycles := 0;
  PROC main()
    WHILE TRUE DO
      WaitDI diStart, 1;
      WHILE DInput(diReady) = 0 DO
        WaitTime 0.1;
      ENDWHILE
      MoveJ pA, v1000, fine, tool0;
      MoveL pB, v500, fine, tool0;
      nCycles := nCycles + 1;
    ENDWHILE
  ENDPROC
ENDMODULE
