%%%
  VERSION:1
  LANGUAGE:ENGLISH
%%%
module Encoded
  ! Müller's cell, 25° - a comment
  const robtarget pA:=[[900,0,900],
      [0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  proc main()
    movej pA,
      v500, fine, tool0;
  endproc
endmodule
