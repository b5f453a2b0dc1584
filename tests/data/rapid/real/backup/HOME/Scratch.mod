MODULE Scratch
    ! operator's scratch module, not loaded in any task
    PROC main()
        WaitTime 99;
    ENDPROC
ENDMODULE
