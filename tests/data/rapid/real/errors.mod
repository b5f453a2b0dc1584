MODULE CellErrors
    PERS tooldata tPen:=[TRUE,[[0,0,150],[1,0,0,0]],[1,[0,0,50],[1,0,0,0],0,0,0]];
    PERS wobjdata wTable:=[FALSE,TRUE,"",[[800,-350,300],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
    CONST robtarget pStart:=[[100,100,0],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget pPark:=[[950,0,700],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    VAR intnum irStop;
    VAR errnum ERR_NOPART:=-1;
    VAR bool bDone:=FALSE;
    VAR num nTries:=0;
    VAR num n:=0;
    VAR num nDivisor:=0;
    VAR num nOffset:=0;
    VAR num nRatio:=0;

    PROC main()
        BookErrNo ERR_NOPART;
        IDelete irStop;
        CONNECT irStop WITH trStop;
        ISignalDI diStopReq, 1, irStop;
        WaitDI diCellReady, 1;
        Visit pPark;
        Visit pStart\WObj:=wTable;
        Visit Offs(pStart,100,0,0)\Slow\WObj:=wTable;
        Visit Offs(pStart,100,100,0), \Slow, \WObj:=wTable;
        CheckPart;
        nRatio := SafeRatio(10);
        ReadOffset;
        Square 4;
        FOR k FROM 1 TO 6 DO
            n := n + 1;
            IF n > 3 n := 0;
            IF bDone RETURN;
            MoveL Offs(pStart, 0, 0, 20 * n), v200, z10, tPen\WObj:=wTable;
        ENDFOR
        IDelete irStop;
    ERROR
        IF ERRNO = ERR_NOPART THEN
            TRYNEXT;
        ENDIF
    ENDPROC

    PROC Visit(robtarget p \switch Slow, \PERS wobjdata WObj)
        VAR speeddata vMove;
        vMove := v500;
        IF Present(Slow) vMove := v100;
        MoveJ Offs(p,0,0,50), vMove, z10, tPen \WObj?WObj;
        MoveL p, vMove, fine, tPen \WObj?WObj;
        MoveL Offs(p,0,0,50), vMove, z10, tPen \WObj?WObj;
    ENDPROC

    PROC CheckPart()
        IF DInput(diPartPresent) = 0 RAISE ERR_NOPART;
        MoveL Offs(pStart,0,0,100), v200, fine, tPen\WObj:=wTable;
    ENDPROC

    FUNC num SafeRatio(num a)
        RETURN a / nDivisor;
    ERROR
        IF ERRNO = ERR_DIVZERO AND nTries < 3 THEN
            nTries := nTries + 1;
            nDivisor := 2;
            RETRY;
        ENDIF
        RAISE;
    ENDFUNC

    PROC ReadOffset()
        nOffset := 100 / (nDivisor - 2);
    ERROR
        nOffset := 0;
        TRYNEXT;
    ENDPROC

    PROC Square(num nSides)
        VAR num k := 0;
      again:
        k := k + 1;
        MoveL Offs(pStart, 100 * ((k DIV 2) MOD 2), 100 * (((k + 1) DIV 2) MOD 2), 0), v200, z5, tPen\WObj:=wTable;
        IF k < nSides GOTO again;
    ENDPROC

    TRAP trStop
        bDone := TRUE;
    ENDTRAP
ENDMODULE
