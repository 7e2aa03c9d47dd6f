// Two particle inclusions in an FEM matrix 80 mm x 50 mm: a disk "inc_a" (radius 12 mm)
// and a tilted square "inc_b" (side 20 mm, turned by 30 degrees): two particle regions,
// each with its own interface (curved; straight with corners).
SetFactory("OpenCASCADE");
Rectangle(1) = {0, 0, 0, 0.08, 0.05};
Disk(2) = {0.022, 0.025, 0, 0.012, 0.012};
Rectangle(3) = {0.045, 0.015, 0, 0.02, 0.02};
Rotate {{0, 0, 1}, {0.055, 0.025, 0}, Pi/6} { Surface{3}; }
BooleanFragments{ Surface{1}; Delete; }{ Surface{2, 3}; Delete; }
a() = Surface In BoundingBox{0.0099, 0.0129, -1, 0.0341, 0.0371, 1};
b() = Surface In BoundingBox{0.041, 0.011, -1, 0.069, 0.039, 1};
rest() = Surface{:};
rest() -= a();
rest() -= b();
Physical Surface("inc_a") = a();
Physical Surface("inc_b") = b();
Physical Surface("matrix") = rest();
