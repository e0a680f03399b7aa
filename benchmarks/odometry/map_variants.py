# /usr/bin/python3 benchmarks/odometry/map_variants.py BENCH_OUT NAME=ODOMETRY_YAML [NAME=ODOMETRY_YAML ...]
#     [--prior doppler] [--jobs 2]
# `dorado bench` runs its maps without an odometry config; this runs `dorado map --odometry-config` on every
# sequence of a bench output (BENCH_OUT/data/SEQ) once per named odometry config, into
# BENCH_OUT/runs/SEQ/map_PRIOR@NAME, niced, skipping runs already there, so that attitude_table.py scores them
# beside the bench's own runs. DORADO=path of the CLI (default build/apps/dorado).
import concurrent.futures, glob, os, subprocess, sys

args = sys.argv[1:]
prior, jobs = 'doppler', 2
if '--prior' in args:
    i = args.index('--prior'); prior = args[i + 1]; del args[i:i + 2]
if '--jobs' in args:
    i = args.index('--jobs'); jobs = int(args[i + 1]); del args[i:i + 2]
out, variants = args[0], [a.split('=', 1) for a in args[1:]]
dorado = os.environ.get('DORADO', 'build/apps/dorado')

def run(seq_dir, name, config):
    seq = os.path.basename(seq_dir)
    dest = os.path.join(out, 'runs', seq, f'map_{prior}@{name}')
    if os.path.exists(os.path.join(dest, 'summary.json')):
        return f'{seq} {name}: kept'
    r = subprocess.run(['nice', dorado, 'map', seq_dir, '--prior', prior, '--accept-implausible', '--out', dest,
                        '--odometry-config', config], capture_output=True, text=True)
    return f'{seq} {name}: rc {r.returncode} {r.stderr.strip().splitlines()[-1] if r.stderr.strip() else ""}'

tasks = [(d, n, c) for d in sorted(glob.glob(os.path.join(out, 'data', '*'))) for n, c in variants]
with concurrent.futures.ThreadPoolExecutor(jobs) as pool:
    for line in pool.map(lambda t: run(*t), tasks):
        print(line, flush=True)
