%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%

MODULE SocketServer
    !*********************************************************
    ! Position server. A PC connects on port 1025 and sends
    ! "x y z" (mm, base frame); the robot goes there and
    ! answers "ok", or "bad" for a message it cannot read.
    ! It waits as long as it takes: \Time:=WAIT_MAX.
    !*********************************************************
    VAR socketdev server_socket;
    VAR socketdev client_socket;
    VAR string client_ip;
    VAR string received_msg;
    VAR num coords{3};
    VAR bool move_ok;
    CONST robtarget pHome:=[[900,0,900],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
    VAR robtarget pTarget:=[[900,0,700],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

    PROC main()
        ConfL\Off;
        MoveJ pHome,v1000,fine,tool0;
        SocketCreate server_socket;
        SocketBind server_socket,"127.0.0.1",1025;
        SocketListen server_socket;
        SocketAccept server_socket,client_socket\ClientAddress:=client_ip\Time:=WAIT_MAX;
        TPWrite "Connected to "+client_ip;
        WHILE TRUE DO
            SocketReceive client_socket\Str:=received_msg\Time:=WAIT_MAX;
            move_ok:=ParseCoords(received_msg);
            IF move_ok THEN
                pTarget.trans:=[coords{1},coords{2},coords{3}];
                MoveL pTarget,v500,fine,tool0;
                SocketSend client_socket\Str:="ok";
            ELSE
                SocketSend client_socket\Str:="bad";
            ENDIF
        ENDWHILE
    ERROR
        IF ERRNO=ERR_SOCK_TIMEOUT THEN
            RETRY;
        ELSEIF ERRNO=ERR_SOCK_CLOSED THEN
            SocketClose client_socket;
            SocketClose server_socket;
        ENDIF
    ENDPROC

    FUNC bool ParseCoords(string msg)
        VAR num first;
        VAR num second;
        first:=StrFind(msg,1," ");
        second:=StrFind(msg,first+1," ");
        IF second>StrLen(msg) RETURN FALSE;
        IF NOT StrToVal(StrPart(msg,1,first-1),coords{1}) RETURN FALSE;
        IF NOT StrToVal(StrPart(msg,first+1,second-first-1),coords{2}) RETURN FALSE;
        IF NOT StrToVal(StrPart(msg,second+1,StrLen(msg)-second),coords{3}) RETURN FALSE;
        RETURN TRUE;
    ENDFUNC
ENDMODULE
