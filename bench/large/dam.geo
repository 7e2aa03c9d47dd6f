// A concrete gravity dam for the large-model benchmark: the cross-section in the x-z plane
// (upstream face vertical at x = 0, crest 6 m wide at 40 m, downstream face down to the toe at
// x = 30 m), extruded 60 m along y. Physical groups: the dam, its base (z = 0) and its
// upstream face (x = 0), where the reservoir pushes.
SetFactory("OpenCASCADE");
Point(1) = {0, 0, 0};
Point(2) = {30, 0, 0};
Point(3) = {6, 0, 34};
Point(4) = {6, 0, 40};
Point(5) = {0, 0, 40};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 1};
Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};
out[] = Extrude {0, 60, 0} { Surface{1}; };
Physical Volume("dam") = {out[1]};
Physical Surface("base") = {out[2]};
Physical Surface("upstream") = {out[6]};
