MODULE pick_table
    ! Pick three parts off a table in front of the robot, place them on a tilted rack beside it.
    PERS tooldata tGrip:=[TRUE,[[0,0,150],[1,0,0,0]],[2,[0,0,60],[1,0,0,0],0,0,0]];
    TASK PERS wobjdata wTable:=[FALSE,TRUE,"",[[800,-300,300],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
    CONST robtarget pPick:=[[100,0,0],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget pPlace:=[[300,700,250],[0,0.258819,0.965926,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    VAR num nPart:=0;

    PROC main()
        ConfJ\Off;
        ConfL\Off;
        FOR i FROM 0 TO 2 DO
            nPart:=i;
            MoveJ Offs(pPick,i*150,0,150),v1000,z50,tGrip\WObj:=wTable;
            MoveL Offs(pPick,i*150,0,0),v300,fine,tGrip\WObj:=wTable;
            WaitTime 0.2;
            MoveL Offs(pPick,i*150,0,150),v1000,z20,tGrip\WObj:=wTable;
            MoveJ Offs(pPlace,0,i*-120,100),v1000,z50,tGrip\WObj:=wTable;
            MoveL Offs(pPlace,0,i*-120,0),v300,fine,tGrip\WObj:=wTable;
            WaitTime 0.2;
            MoveL Offs(pPlace,0,i*-120,100),v1000,z50,tGrip\WObj:=wTable;
        ENDFOR
    ENDPROC
ENDMODULE
