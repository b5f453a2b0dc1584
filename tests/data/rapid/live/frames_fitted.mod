MODULE C
  VAR robtarget a{4} := [[[0,0,0],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]],[[100,0,0],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]],[[0,100,0],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]],[[0,0,100],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]]];
  VAR robtarget b{4};
  VAR robtarget c{4} := [[[600,0,0],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]],[[500,100,0],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]],[[400,0,0],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]],[[500,-100,0],[1,0,0,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]]];
  VAR num mx; VAR num mn;
  VAR pose f; VAR pose g;
  PROC main()
    FOR i FROM 1 TO 4 DO
      b{i} := a{i};
      b{i}.trans := [-a{i}.trans.y + 10, a{i}.trans.x + 20, a{i}.trans.z + 30];
    ENDFOR
    f := DefAccFrame(a, b, 4, mx, mn);
    g := CalcRotAxisFrame(STN_1, c, 4, mx, mn);
  ENDPROC
ENDMODULE
