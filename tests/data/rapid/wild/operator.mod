MODULE Operator
  ! Stacking: the layer count and height come from the operator, the
  ! x offset and the last part's shift from files on the controller.
  CONST robtarget pStack:=[[1000,0,400],[0,0,1,0],[0,0,0,0],[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]];
  VAR num nLayers:=0;
  VAR num nHeight:=0;
  VAR num nOffset:=0;
  VAR pos vShift:=[0,0,0];
  VAR iodev recipe;
  VAR iodev shiftfile;

  PROC main()
    ConfL\Off;
    MoveJ Offs(pStack,0,0,400),v1000,fine,tool0;
    TPReadNum nLayers,"How many layers?";
    nHeight:=UINumEntry(\Header:="Recipe"\Message:="Layer height (mm)?"\InitValue:=50\MinValue:=10\MaxValue:=200);
    Open "HOME:"\File:="recipe.txt",recipe\Read;
    nOffset:=ReadNum(recipe);
    Close recipe;
    Open "HOME:"\File:="shift.bin",shiftfile\Bin;
    ReadAnyBin shiftfile,vShift;
    Close shiftfile;
    FOR i FROM 1 TO nLayers DO
      MoveL Offs(pStack,nOffset,0,(i-1)*nHeight),v500,fine,tool0;
    ENDFOR
    MoveL Offs(pStack,vShift.x,vShift.y,vShift.z),v500,fine,tool0;
    MoveJ Offs(pStack,0,0,400),v1000,fine,tool0;
  ENDPROC
ENDMODULE
