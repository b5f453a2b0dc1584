MODULE Calib
    ! Two points a PC writes before the run; the interpolation between them divides by their
    ! difference, which is 0 until the PC has written them.
    PERS num x1:=0;
    PERS num x2:=0;
    PERS num v1:=0;
    PERS num v2:=0;
    CONST robtarget pHome:=[[900,0,900],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

    PROC main()
        MoveJ pHome, v1000, fine, tool0;
        MoveL Offs(pHome,0,100,0), v500, fine, tool0;
        Measure;
        MoveL Offs(pHome,0,0,0), v500, fine, tool0;
    ENDPROC

    PROC Measure()
        VAR num Kx;
        Kx := (x2 - x1) / (v2 - v1);
        MoveL Offs(pHome,Kx,0,0), v500, fine, tool0;
    ENDPROC
ENDMODULE
