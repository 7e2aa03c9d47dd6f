// A layered sedimentary cover on a rough rigid base, pushed by a piston, in metres. The
// cover (4 layers of 62.5 m, 5 km long) ends free at x = 0; the base (5 m of fixed fine
// grains that set the basal friction) reaches 1 km further, so the cover's free end rests on
// it. The piston (50 m wide, 500 m tall) stands on the base at the cover's other end.
L = 5000;
ext = 1000;
hb = 5;
h = 62.5;
Point(1) = {-ext, 0, 0};
Point(2) = {L, 0, 0};
Point(3) = {L, hb, 0};
Point(4) = {0, hb, 0};
Point(5) = {-ext, hb, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 1};
Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};
For k In {1:4}
  Point(10 + 2 * k) = {0, hb + k * h, 0};
  Point(11 + 2 * k) = {L, hb + k * h, 0};
  Line(30 + k) = {10 + 2 * k, 11 + 2 * k};  // top of layer k
EndFor
Line(41) = {4, 12};
Line(51) = {3, 13};
Curve Loop(2) = {-3, 51, -31, -41};
Plane Surface(2) = {2};
For k In {2:4}
  Line(40 + k) = {8 + 2 * k, 10 + 2 * k};
  Line(50 + k) = {9 + 2 * k, 11 + 2 * k};
  Curve Loop(1 + k) = {29 + k, 50 + k, -(30 + k), -(40 + k)};
  Plane Surface(1 + k) = {1 + k};
EndFor
Point(31) = {L + 50, hb, 0};
Point(32) = {L + 50, hb + 500, 0};
Point(33) = {L, hb + 500, 0};
Line(60) = {3, 31};
Line(61) = {31, 32};
Line(62) = {32, 33};
Line(63) = {33, 3};
Curve Loop(10) = {60, 61, 62, 63};
Plane Surface(10) = {10};
Physical Surface("piston") = {10};
Physical Surface("base") = {1};
Physical Surface("cover") = {2, 3, 4, 5};
Physical Surface("layer1") = {2};
Physical Surface("layer2") = {3};
Physical Surface("layer3") = {4};
Physical Surface("layer4") = {5};
