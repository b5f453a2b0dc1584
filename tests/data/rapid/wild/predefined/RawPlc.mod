MODULE RawPlc
    ! Layer heights from the line PLC as raw bytes: the robot asks for a
    ! pallet (a DINT request number and a UINT spare word), the PLC answers
    ! a 4-byte DINT layer count and a 4-byte float layer height.
    VAR socketdev plc;
    VAR rawbytes raw_out;
    VAR rawbytes raw_in;
    VAR num nRequest:=1;
    VAR num nLayers;
    VAR num nHeight;
    CONST robtarget pPallet:=[[800,-400,300],[0,0,1,0],[-1,0,-1,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];

    PROC main()
        MoveJ Offs(pPallet,0,0,400),v1000,z50,tool0;
        SocketCreate plc;
        SocketConnect plc,"192.168.125.10",2000\Time:=WAIT_MAX;
        ClearRawBytes raw_out;
        PackRawBytes nRequest,raw_out,1\IntX:=DINT;
        PackRawBytes 0,raw_out,RawBytesLen(raw_out)+1\IntX:=UINT;
        SocketSend plc\RawData:=raw_out;
        SocketReceive plc\RawData:=raw_in\Time:=WAIT_MAX;
        UnpackRawBytes raw_in,1,nLayers\IntX:=DINT;
        UnpackRawBytes raw_in,5,nHeight\Float4;
        FOR i FROM 1 TO nLayers DO
            MoveL Offs(pPallet,0,0,i*nHeight+100),v1000,z50,tool0;
            MoveL Offs(pPallet,0,0,i*nHeight),v200,fine,tool0;
            MoveL Offs(pPallet,0,0,i*nHeight+100),v1000,z50,tool0;
        ENDFOR
        SocketClose plc;
    ENDPROC
ENDMODULE
