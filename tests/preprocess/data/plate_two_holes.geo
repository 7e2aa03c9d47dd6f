// A 2D plate with two circular holes (the double-hole blast plate of Zhao, Qiao, Zhang, Sun &
// Chen 2021, scaled):
// 0.2 m x 0.1 m, holes of radius 0.01 m centred at (0.05, 0.05) and (0.15, 0.05).
// Area = 0.02 - 2*pi*1e-4 = 0.019371681 m^2.
W = 0.2; H = 0.1; R = 0.01; lc = 0.01;
Point(1) = {0, 0, 0, lc}; Point(2) = {W, 0, 0, lc}; Point(3) = {W, H, 0, lc}; Point(4) = {0, H, 0, lc};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
For k In {0:1}
  cx = 0.05 + 0.1 * k;
  c = newp; Point(c) = {cx, H / 2, 0, lc / 2};
  p1 = newp; Point(p1) = {cx + R, H / 2, 0, lc / 2};
  p2 = newp; Point(p2) = {cx - R, H / 2, 0, lc / 2};
  a1 = newc; Circle(a1) = {p1, c, p2};
  a2 = newc; Circle(a2) = {p2, c, p1};
  hole[k] = newll; Curve Loop(hole[k]) = {a1, a2};
  arcs[2 * k] = a1; arcs[2 * k + 1] = a2;
EndFor
Plane Surface(1) = {1, hole[0], hole[1]};
Physical Surface("rock") = {1};
Physical Curve("hole1") = {arcs[0], arcs[1]};
Physical Curve("hole2") = {arcs[2], arcs[3]};
Physical Curve("bottom") = {1};
Physical Curve("top") = {3};
