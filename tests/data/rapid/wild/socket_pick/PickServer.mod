%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%

MODULE PickServer
    !*****************************************************
    ! Vision pick. The PC sends "x,y" (mm, base frame) of
    ! the next part on the table; the robot picks it, puts
    ! it on the outfeed and answers "done".
    !*****************************************************
    VAR socketdev sock;
    VAR string receive_string;
    VAR num comma;
    VAR num x;
    VAR num y;
    VAR bool ok;
    VAR num nPicked:=0;
    CONST robtarget pHome:=[[900,0,900],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    VAR robtarget pPick:=[[900,0,400],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    CONST robtarget pPlace:=[[850,-300,450],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

    PROC main()
        ConfJ\Off;
        ConfL\Off;
        MoveJ pHome,v1000,fine,tVac;
        SocketCreate sock;
        SocketConnect sock,"192.168.125.5",3000;
        SocketSend sock\Str:="ready";
        WHILE TRUE DO
            SocketReceive sock\Str:=receive_string;
            comma:=StrFind(receive_string,1,",");
            ok:=StrToVal(StrPart(receive_string,1,comma-1),x);
            ok:=StrToVal(StrPart(receive_string,comma+1,StrLen(receive_string)-comma),y);
            pPick.trans.x:=x;
            pPick.trans.y:=y;
            MoveJ Offs(pPick,0,0,100),v1000,z50,tVac;
            MoveL pPick,v200,fine,tVac;
            SetDO doVacuum,1;
            WaitTime 0.2;
            MoveL Offs(pPick,0,0,100),v500,z50,tVac;
            MoveJ Offs(pPlace,0,0,100),v1000,z50,tVac;
            MoveL pPlace,v200,fine,tVac;
            SetDO doVacuum,0;
            MoveL Offs(pPlace,0,0,100),v500,z50,tVac;
            Incr nPicked;
            SocketSend sock\Str:="done "+NumToStr(nPicked,0);
        ENDWHILE
    ERROR
        IF ERRNO=ERR_SOCK_TIMEOUT THEN
            RETRY;
        ENDIF
    ENDPROC
ENDMODULE
