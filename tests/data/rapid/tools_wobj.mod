MODULE ToolsWobj
  PERS tooldata tLong:=[TRUE,[[0,0,150],[1,0,0,0]],[1,[0,0,50],[1,0,0,0],0,0,0]];
  PERS wobjdata wShifted:=[FALSE,TRUE,"",[[100,0,0],[1,0,0,0]],[[0,0,50],[1,0,0,0]]];
  CONST robtarget pA:=[[900,0,900],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    MoveJ pA, v500, fine, tLong\WObj:=wShifted;
    MoveL pA, v100, fine, tool0;
  ENDPROC
ENDMODULE
