import sys, warnings; sys.path.insert(0,'tests'); warnings.simplefilter("ignore")
import numpy as np, zoo, test_zoo_inputs as T
for seed in map(int, sys.argv[1:]):
    s=T.input_scene(seed); print(s)
    print(s.scene.grasp, s.scene.stops, type(s.scene.motion).__name__)
    out=zoo.check_scene(s.zs, methods=("event","implicit","explicit"), agree=("event","implicit","explicit"))
    for k,v in out.items():
        print(k, {a:(np.round(b,12) if isinstance(b,float) else b) for a,b in v.items() if a not in('pose','dt')})
