MODULE JointZone
  ! Two MoveJ meeting at a corner at pB: with z50 the first hands over to the second where the
  ! TCP comes within 50 mm of pB (a test swaps z50 for z10 and fine).
  CONST robtarget pA:=[[1000,-200,700],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pB:=[[1000,100,700],[0,0,1,0],[0,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pC:=[[1300,100,700],[0,0,1,0],[0,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    ConfJ \Off;
    MoveJ pA, v1000, fine, tool0;
    MoveJ pB, v1000, z50, tool0;
    MoveJ pC, v1000, fine, tool0;
  ENDPROC
ENDMODULE
