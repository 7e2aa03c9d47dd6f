// A rock plate 500 x 250 mm with two blast holes of 10 mm diameter on its horizontal centre
// line, 100 mm apart (the double-hole blast of Zhao, Qiao, Zhang, Sun & Chen 2021). Lengths in
// metres; the plate's lower left corner is at the origin.
W = 0.5; H = 0.25; R = 0.005; lc = 0.02;
Point(1) = {0, 0, 0, lc}; Point(2) = {W, 0, 0, lc}; Point(3) = {W, H, 0, lc}; Point(4) = {0, H, 0, lc};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
For k In {0:1}
  cx = W / 2 - 0.05 + 0.1 * k;
  c = newp; Point(c) = {cx, H / 2, 0, R / 2};
  p1 = newp; Point(p1) = {cx + R, H / 2, 0, R / 2};
  p2 = newp; Point(p2) = {cx - R, H / 2, 0, R / 2};
  a1 = newc; Circle(a1) = {p1, c, p2};
  a2 = newc; Circle(a2) = {p2, c, p1};
  hole[k] = newll; Curve Loop(hole[k]) = {a1, a2};
EndFor
Plane Surface(1) = {1, hole[0], hole[1]};
Physical Surface("rock") = {1};
