%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%

MODULE PalletData
  ! The cell's tool, the pallet's work object and the taught points. The pallet was moved 330 mm
  ! farther out: its far row (row 2) is now beyond the IRB 2600-12/1.65's reach.
  PERS tooldata tGripper:=[TRUE,[[0,0,180],[1,0,0,0]],[8,[0,0,90],[1,0,0,0],0,0,0]];
  PERS wobjdata wPallet:=[FALSE,TRUE,"",[[1000,-600,100],[1,0,0,0]],[[0,0,0],[1,0,0,0]]];
  CONST robtarget pPick:=[[600,700,300],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pPlace:=[[0,0,0],[0,0,1,0],[-1,0,-1,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST jointtarget jHome:=[[0,-10,20,0,60,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST num nPitchX:=330;
  CONST num nPitchY:=250;
  CONST num nApproach:=150;
ENDMODULE
