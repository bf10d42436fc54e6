"""A/B of two builds of the uvflat CLI in one run, interleaved (the order alternates per round):
ABF++ on the 18 public disks and the natural conformal map on disk_face_libigl_loop1 (207k
faces). Prints, per mesh, the medians of the solve time the CLI's --json reports and of the whole
process's wall time, and whether both builds give the same angle error and flip count.

usage: python3 benches/ab_cli.py BEFORE/uvflat AFTER/uvflat tests/data/meshes ROUNDS
"""
import json, subprocess, sys, time, statistics, os, gzip, shutil, tempfile
before, after, meshes, rounds = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
tmp = tempfile.mkdtemp()
def unpack(name):
    out = os.path.join(tmp, name)
    with gzip.open(os.path.join(meshes, name + ".gz")) as f, open(out, "wb") as g:
        shutil.copyfileobj(f, g)
    return out
disks = sorted(n[:-3] for n in os.listdir(meshes) if n.startswith("disk_") and n.endswith(".obj.gz") and "_loop" not in n)
cases = [(d, "abf++") for d in disks] + [("disk_face_libigl_loop1.obj", "natural-conformal")]
files = {d: unpack(d) for d, _ in cases}
res = {}
for r in range(rounds):
    for d, m in cases:
        for tag, exe in (("before", before), ("after", after)) if r % 2 == 0 else (("after", after), ("before", before)):
            t0 = time.perf_counter()
            o = subprocess.run([exe, "unwrap", files[d], "-o", os.path.join(tmp, "out.obj"), "--method", m, "--json"], capture_output=True, text=True)
            wall = time.perf_counter() - t0
            j = json.loads(o.stdout)
            res.setdefault((d, m, tag), []).append((j["seconds"], wall, j.get("angle_mean"), j.get("flipped")))
print(f"{'mesh':<34} {'method':<18} {'solve before':>12} {'after':>8} {'ratio':>6} | {'wall before':>11} {'after':>8} {'ratio':>6} | same result")
tot = {"before": [0, 0], "after": [0, 0]}
ratios = []
for d, m in cases:
    b, a = res[(d, m, "before")], res[(d, m, "after")]
    sb, sa = statistics.median(x[0] for x in b), statistics.median(x[0] for x in a)
    wb, wa = statistics.median(x[1] for x in b), statistics.median(x[1] for x in a)
    same = b[0][2] == a[0][2] and b[0][3] == a[0][3]
    ratios.append(sa / sb)
    for k, v in (("before", (sb, wb)), ("after", (sa, wa))):
        tot[k][0] += v[0]; tot[k][1] += v[1]
    print(f"{d:<34} {m:<18} {sb:>12.4f} {sa:>8.4f} {sa/sb:>6.3f} | {wb:>11.4f} {wa:>8.4f} {wa/wb:>6.3f} | {same}")
print(f"sum solve before {tot['before'][0]:.3f} after {tot['after'][0]:.3f} ratio {tot['after'][0]/tot['before'][0]:.3f}; "
      f"sum wall before {tot['before'][1]:.3f} after {tot['after'][1]:.3f} ratio {tot['after'][1]/tot['before'][1]:.3f}; "
      f"median per-mesh solve ratio {statistics.median(ratios):.3f}")
