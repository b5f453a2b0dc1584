%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%

MODULE Vectors(NOSTEPIN)
  ! Builds the approach from vectors and from a recipe read as text.
  CONST robtarget p0:=[[900,0,500],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  VAR pos vA:=[1,0,0];
  VAR pos vB:=[0,1,0];
  VAR pos vZ;
  VAR pos vX;
  VAR pos vRead;
  VAR num nRead;
  VAR bool bRead;
  VAR bool ok1;
  VAR bool ok2;
  VAR bool ok3;
  VAR num nMatch;
  VAR num nNoMatch;
  VAR string sMapped;
  VAR num grid{2,3}:=[[1,2,3],[4,5,6]];
  VAR num nBefore;

  PROC main()
    vZ:=vA*vB;
    vX:=CrossProd([0,1,0],[0,0,1]);
    ok1:=StrToVal("[600,500,225.3]",vRead);
    ok2:=StrToVal("42.5",nRead);
    ok3:=StrToVal("TRUE",bRead);
    nMatch:=StrMatch("robot_target_17",1,"target");
    nNoMatch:=StrMatch("robot",1,"xyz");
    sMapped:=StrMap("1-2-3","-",".");
    nBefore:=grid{2,3};
    grid:=[[0,0,2],[1,0,0]];
    MoveJ Offs(p0,0,0,200),v1000,fine,tool0;
    MoveL Offs(p0,grid{2,1}*100,grid{1,3}*50,vZ.z*100),v500,fine,tool0;
    IF bRead THEN
      MoveL Offs(p0,vX.x*50,vRead.x-600,nRead),v500,fine,tool0;
    ENDIF
  ENDPROC
ENDMODULE
