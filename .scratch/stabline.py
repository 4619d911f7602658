import os, sys, threading, time, traceback, warnings
import numpy as np, hbmfric as hf
warnings.simplefilter("ignore")
exec(open(".scratch/nmmem.py").read().split("n = int(sys.argv[1])")[0].split("def peak")[1].split("\n",1)[1])
def rss():
    with open("/proc/self/status") as f:
        for l in f:
            if l.startswith("VmRSS"): return int(l.split()[1])/1024
n = int(sys.argv[1]); H = int(sys.argv[2])
s0 = chain(12, 1); b0 = hf.frf(s0, 0.1, (0.3, 0.32), harmonics=3, condense=False); b0.stability(method="hill")
b = hf.frf(chain(n, 1), 0.1, (0.30, 0.31), harmonics=H, condense=False, max_steps=6)
main = threading.main_thread().ident
log = []; stop = [False]; best=[0]
def sampler():
    while not stop[0]:
        r = rss()
        if r > best[0] + 8:
            st = traceback.extract_stack(sys._current_frames()[main])
            best[0] = r; log.append((r, " < ".join(f"{f.name}:{f.lineno}" for f in st[-6:][::-1])))
        time.sleep(0.002)
base = rss(); best[0]=base
th = threading.Thread(target=sampler, daemon=True); th.start()
b.stability(method="hill")
stop[0] = True; th.join()
for r, st in log: print(f"{r-base:7.0f} {st}")
