// A rock plate with two circular holes on its horizontal centre line, loaded in uniaxial
// compression between its top and bottom edges. Lengths in metres.
W = 0.2; H = 0.1; R = 0.008; lc = 0.01;
Point(1) = {0, 0, 0, lc}; Point(2) = {W, 0, 0, lc}; Point(3) = {W, H, 0, lc}; Point(4) = {0, H, 0, lc};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
For k In {0:1}
  cx = 0.07 + 0.06 * k;
  c = newp; Point(c) = {cx, H / 2, 0, lc / 4};
  p1 = newp; Point(p1) = {cx + R, H / 2, 0, lc / 4};
  p2 = newp; Point(p2) = {cx - R, H / 2, 0, lc / 4};
  a1 = newc; Circle(a1) = {p1, c, p2};
  a2 = newc; Circle(a2) = {p2, c, p1};
  hole[k] = newll; Curve Loop(hole[k]) = {a1, a2};
EndFor
Plane Surface(1) = {1, hole[0], hole[1]};
Physical Surface("rock") = {1};
Physical Curve("bottom") = {1};
Physical Curve("top") = {3};
