MODULE MainModule
    ! A cell program as a repository holds it: its tools, work object, speeds and signals live in
    ! CalibData.mod, user.sys and the controller's EIO.cfg, none of which were committed.
    CONST robtarget pApproach:=[[900,-120,500],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget pGlue1:=[[900,-120,300],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget pGlue2:=[[900,120,300],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget pGlue3:=[[1100,120,300],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    VAR num nParts:=0;

    PROC main()
        ConfL \Off;
        ConfJ \Off;
        WHILE TRUE DO
            WaitDI DI_Sensor_Inf, 1;
            MoveJ pApproach, vMedium, z20, Tool_27\WObj:=Workobject_Chapa;
            MoveL pGlue1, vGlue, z5, Tool_27\WObj:=Workobject_Chapa;
            SetDO doGlueOn, 1;
            MoveL pGlue2, vGlue, z5, Tool_27\WObj:=Workobject_Chapa;
            MoveL pGlue3, vGlue, fine, Tool_27\WObj:=Workobject_Chapa;
            SetDO doGlueOn, 0;
            MoveJ pApproach, vMedium, z20, Tool_27\WObj:=Workobject_Chapa;
            nParts := nParts + 1;
            IF nParts >= nBatchSize THEN
                nParts := 0;
            ENDIF
        ENDWHILE
    ENDPROC
ENDMODULE
