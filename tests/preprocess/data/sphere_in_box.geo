// 3D: a spherical particle region "ball" (radius 60 mm) inside an FEM box "box" (200 mm).
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.2, 0.2, 0.2};
Sphere(2) = {0.1, 0.1, 0.1, 0.06};
BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }
ball() = Volume In BoundingBox{0.0399, 0.0399, 0.0399, 0.1601, 0.1601, 0.1601};
rest() = Volume{:};
rest() -= ball();
Physical Volume("ball") = ball();
Physical Volume("box") = rest();
