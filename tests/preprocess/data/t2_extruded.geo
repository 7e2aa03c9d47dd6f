// In the style of gmsh's tutorial t2: the t1 rectangle extruded into a 3D slab
// 0.1 m x 0.3 m x 0.05 m (volume 1.5e-3 m^3), with physical volume and surfaces.
lc = 1e-2;
Point(1) = {0, 0, 0, lc};
Point(2) = {.1, 0, 0, lc};
Point(3) = {.1, .3, 0, lc};
Point(4) = {0, .3, 0, lc};
Line(1) = {1, 2};
Line(2) = {3, 2};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {4, 1, -2, 3};
Plane Surface(1) = {1};
out[] = Extrude {0, 0, 0.05} { Surface{1}; };
Physical Volume("slab") = {out[1]};
Physical Surface("base") = {1};
Physical Surface("lid") = {out[0]};
