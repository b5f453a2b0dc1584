MODULE LateBinding
  ! %"name"% calls and CallByVar pick the procedure by a string at run time.
  VAR num nLast := 0;
  PROC Station1(num n)
    nLast := 10 + n;
  ENDPROC
  PROC Station2(num n)
    nLast := 20 + n;
  ENDPROC
  PROC Job3()
    nLast := 30;
  ENDPROC
  PROC main()
    VAR num k := 2;
    %"Station" + NumToStr(k, 0)% 5;
    CallByVar "Job", 3;
  ENDPROC
ENDMODULE
