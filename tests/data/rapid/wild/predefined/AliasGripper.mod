MODULE AliasGripper
    ! A gripper library written once for every cell: it works on its own
    ! signal variables, aliases of the cell's (EIO.cfg) signals, and counts
    ! parts on the sensor's every edge.
    VAR signaldo doGrip;
    VAR signaldi diGripped;
    VAR intnum irPart;
    VAR num nEdges:=0;
    CONST robtarget pPick:=[[1000,100,450],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget pPlace:=[[850,-300,450],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

    PROC main()
        AliasIO doGripper1,doGrip;
        AliasIO "diGripper1Closed",diGripped;
        IDelete irPart;
        CONNECT irPart WITH PartTrap;
        ISignalDI diPartSensor,edge,irPart;
        IF NOT ValidIO(diPartSensor) THEN
            TPWrite "no part sensor";
        ENDIF
        MoveJ Offs(pPick,0,0,100),v1000,z50,tool0;
        MoveL pPick,v200,fine,tool0;
        SetDO doGrip,high;
        WaitTime 0.3;
        MoveL Offs(pPick,0,0,100),v500,z50,tool0;
        MoveJ Offs(pPlace,0,0,100),v1000,z50,tool0;
        MoveL pPlace,v200,fine,tool0;
        SetDO doGrip,low;
        Blow doBlowOff;
        MoveL Offs(pPlace,0,0,100),v500,z50,tool0;
        AliasIOReset doGrip;
        IDelete irPart;
    ENDPROC

    PROC Blow(VAR signaldo sig)
        PulseDO\PLength:=0.2,sig;
    ENDPROC

    TRAP PartTrap
        Incr nEdges;
    ENDTRAP
ENDMODULE
