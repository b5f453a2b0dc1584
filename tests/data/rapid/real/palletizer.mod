MODULE Palletizer
    ! Palletizing cell: boxes arrive on the infeed conveyor and are stacked on the
    ! pallet in a 3 x 2 pattern, 3 layers. Product type from the PLC (giProduct).
    RECORD palletpattern
        num nRows;
        num nCols;
        num nLayers;
        num dx;
        num dy;
        num dz;
    ENDRECORD

    PERS tooldata tVacuum:=[TRUE,[[0,0,180],[1,0,0,0]],[4.5,[0,0,90],[1,0,0,0],0,0,0]];
    PERS wobjdata wPallet:=[FALSE,TRUE,"",[[700,-400,200],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
    PERS palletpattern patSmall:=[2,3,3,150,120,100];
    PERS palletpattern patLarge:=[2,2,2,220,180,160];
    CONST robtarget pInfeed:=[[350,600,150],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget pBase:=[[80,60,0],[0,0,1,0],[-1,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST jointtarget jSafe:=[[0,-10,10,0,60,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    VAR palletpattern pat;
    VAR num nBox:=0;
    VAR num nProduct:=0;
    VAR robtarget pDrop;

    PROC main()
        MoveAbsJ jSafe\NoEOffs, v1000, z50, tVacuum;
        WHILE TRUE DO
            nProduct := GInput(giProduct);
            TEST nProduct
            CASE 0, 1:
                pat := patSmall;
            CASE 2:
                pat := patLarge;
            DEFAULT:
                TPWrite "Unknown product " \Num:=nProduct;
                Stop;
            ENDTEST
            BuildPallet;
            WaitDI diPalletEmpty, 1;
        ENDWHILE
    ENDPROC

    PROC BuildPallet()
        VAR num nPerLayer;
        VAR num row;
        VAR num col;
        nPerLayer := pat.nRows * pat.nCols;
        FOR layer FROM 0 TO pat.nLayers - 1 DO
            FOR n FROM 0 TO nPerLayer - 1 DO
                row := n DIV pat.nCols;
                col := n MOD pat.nCols;
                pDrop := Offs(pBase, col * pat.dx, row * pat.dy, layer * pat.dz);
                PickBox;
                PlaceBox pDrop;
                nBox := nBox + 1;
            ENDFOR
        ENDFOR
    ENDPROC

    PROC PickBox()
        MoveJ RelTool(pInfeed, 0, 0, -200), v2000, z50, tVacuum\WObj:=wPallet;
        MoveL pInfeed, v500, fine, tVacuum\WObj:=wPallet;
        SetDO doVacuum, 1;
        WaitDI diVacuumOk, 1\MaxTime:=2;
        MoveL RelTool(pInfeed, 0, 0, -200), v1000, z50, tVacuum\WObj:=wPallet;
    ENDPROC

    PROC PlaceBox(robtarget pTarget)
        MoveJ RelTool(pTarget, 0, 0, -250 \Rz:=90), v2000, z100, tVacuum\WObj:=wPallet;
        MoveL RelTool(pTarget, 0, 0, 0 \Rz:=90), v300, fine, tVacuum\WObj:=wPallet;
        SetDO doVacuum, 0;
        WaitTime 0.15;
        MoveL RelTool(pTarget, 0, 0, -250 \Rz:=90), v1000, z50, tVacuum\WObj:=wPallet;
    ENDPROC
ENDMODULE
