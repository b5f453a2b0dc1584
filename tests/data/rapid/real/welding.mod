MODULE Welding
    ! Fillet weld on a bracket: search the plate edge, shift the object frame,
    ! then weld a line, an arc and a line. Torch with a 30 degree neck.
    PERS tooldata tWeldGun:=[TRUE,[[120,0,380],[0.965926,0,0.258819,0]],[2.8,[30,0,150],[1,0,0,0],0,0,0]];
    TASK PERS wobjdata wobjWeld:=[FALSE,TRUE,"",[[850,-250,400],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
    PERS seamdata seam1:=[0.5,0.5,[5,0,24,120,0,0,0,0,0],0.5,0,0,0,0,[0,0,0,0,0,0,0,0,0],0,0,[5,0,24,120,0,0,0,0,0],0,0,[0,0,0,0,0,0,0,0,0],0];
    PERS welddata weld1:=[8,0,[5,0,22.5,180,0,0,0,0,0],[0,0,0,0,0,0,0,0,0]];
    PERS weavedata weave1:=[1,0,4,3,0,0,0,0,0,0,0,0,0,0,0];
    CONST robtarget pApproach:=[[0,0,120],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget pSearchStart:=[[-40,0,10],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget pSearchEnd:=[[10,0,10],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget pNominal:=[[0,0,10],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget p10:=[[0,0,0],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget p20:=[[250,0,0],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget p30:=[[321,29,0],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget p40:=[[350,100,0],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    CONST robtarget p50:=[[350,300,0],[0,0,1,0],[0,-1,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
    VAR robtarget pFound;
    VAR triggdata trGasOn;
    VAR num nWelds:=0;

    PROC main()
        SearchEdge;
        WeldBracket;
        MoveLDO Offs(p50,0,0,150), v1000, z50, tWeldGun\WObj:=wobjWeld, doTorchClean, 1;
        MoveJ pApproach, v1000, fine, tWeldGun\WObj:=wobjWeld;
    ENDPROC

    PROC SearchEdge()
        wobjWeld.oframe := [[0,0,0],[1,0,0,0]];
        MoveJ pApproach, v1000, z50, tWeldGun\WObj:=wobjWeld;
        MoveL pSearchStart, v200, fine, tWeldGun\WObj:=wobjWeld;
        SearchL \Stop, diWireTouch, pFound, pSearchEnd, v20, tWeldGun\WObj:=wobjWeld;
        ! shift the object frame by what the search found
        wobjWeld.oframe.trans := pFound.trans - pNominal.trans;
        MoveL pSearchStart, v200, z10, tWeldGun\WObj:=wobjWeld;
    ERROR
        IF ERRNO = ERR_WHLSEARCH THEN
            TPWrite "Edge not found";
            RAISE;
        ENDIF
    ENDPROC

    PROC WeldBracket()
        TriggIO trGasOn, 20 \Start \DOp:=doGasOn, 1;
        TriggL Offs(p10,0,0,30), v500, trGasOn, z5, tWeldGun\WObj:=wobjWeld;
        ArcLStart p10, v200, seam1, weld1, fine, tWeldGun\WObj:=wobjWeld;
        ArcL p20, v100, seam1, weld1\Weave:=weave1, z1, tWeldGun\WObj:=wobjWeld;
        ArcC p30, p40, v100, seam1, weld1\Weave:=weave1, z1, tWeldGun\WObj:=wobjWeld;
        ArcLEnd p50, v100, seam1, weld1, fine, tWeldGun\WObj:=wobjWeld;
        Incr nWelds;
    ENDPROC
ENDMODULE
