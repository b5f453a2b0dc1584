MODULE SystemData
    ! The controller's own data read as real cells read it: the motion
    ! settings, the program displacement, the task's robot, the option
    ! constants of EGM and PickMaster, a raw-data integer type.
    VAR egmident egmID1;
    VAR num nOverride;
    VAR num nEoffs;
    VAR num nFrame;
    VAR num nIntType;
    VAR errnum nPmErr;
    CONST robtarget pStart:=[[900,0,800],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST pose pCorr:=[[0,0,0],[1,0,0,0]];
    CONST egm_minmax egm_lin:=[-1,1];

    PROC main()
        nOverride:=C_MOTSET.vel.oride;
        nEoffs:=C_PROGDISP.eoffs.eax_a;
        nFrame:=EGM_FRAME_WOBJ;
        nIntType:=ULINT;
        nPmErr:=PM_ERR_JOB_EMPTY;
        MotionProcessModeSet OPTIMAL_CYCLE_TIME_MODE;
        TPShow TP_LATEST;
        IF nOverride<100 THEN
            VelSet 100,5000;
        ENDIF
        MoveJ pStart,v1000,fine,tool0;
        EGMGetId egmID1;
        EGMSetupUC ROB_ID,egmID1,"default","UCdevice:"\Pose;
        EGMActPose egmID1\Tool:=tool0\WObj:=wobj0,pCorr,EGM_FRAME_WOBJ,pCorr,EGM_FRAME_WOBJ\x:=egm_lin\y:=egm_lin\z:=egm_lin;
        EGMStop egmID1,EGM_STOP_HOLD;
        MoveL Offs(pStart,0,0,-100),v200,fine,tool0;
    ERROR
        IF ERRNO=PM_ERR_JOB_EMPTY THEN
            TRYNEXT;
        ENDIF
    ENDPROC
ENDMODULE
