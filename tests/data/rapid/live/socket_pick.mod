MODULE SockPick
  VAR socketdev sock;
  VAR string receive_string;
  VAR num x;
  VAR num y;
  VAR bool ok;
  VAR num comma;
  CONST robtarget pHome := [[900,0,900],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  VAR robtarget pPick := [[900,0,600],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    SocketCreate sock;
    SocketConnect sock, "192.168.0.10", 1025;
    MoveJ pHome, v1000, fine, tool0;
    WHILE TRUE DO
      SocketReceive sock \Str:=receive_string;
      comma := StrFind(receive_string, 1, ",");
      ok := StrToVal(StrPart(receive_string, 1, comma - 1), x);
      ok := StrToVal(StrPart(receive_string, comma + 1, StrLen(receive_string) - comma), y);
      pPick.trans.x := x;
      pPick.trans.y := y;
      MoveL Offs(pPick, 0, 0, 100), v1000, z10, tool0;
      MoveL pPick, v200, fine, tool0;
      SocketSend sock \Str:="done";
    ENDWHILE
  ENDPROC
ENDMODULE
