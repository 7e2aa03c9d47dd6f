// A circular particle region ("disk", radius 15 mm) inside a square FEM region ("fem",
// 60 mm): one curved interface. OpenCASCADE fragments make the circle a shared curve.
SetFactory("OpenCASCADE");
Rectangle(1) = {0, 0, 0, 0.06, 0.06};
Disk(2) = {0.03, 0.03, 0, 0.015, 0.015};
BooleanFragments{ Surface{1}; Delete; }{ Surface{2}; Delete; }
disk() = Surface In BoundingBox{0.0149, 0.0149, -1, 0.0451, 0.0451, 1};
rest() = Surface{:};
rest() -= disk();
Physical Surface("disk") = disk();
Physical Surface("fem") = rest();
