MODULE Singular
  CONST jointtarget jStraight:=[[0,0,0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pStraight:=[[1030,0,1260],[0.7071068,0,0.7071068,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    MoveAbsJ jStraight, v500, fine, tool0;
    MoveL Offs(pStraight,-200,0,0), v200, fine, tool0;
  ENDPROC
ENDMODULE
