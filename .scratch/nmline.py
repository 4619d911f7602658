import os, sys, threading, time, traceback, warnings
exec(open(".scratch/nmmem.py").read().split("n = int(sys.argv[1])")[0])
def rss():
    with open("/proc/self/status") as f:
        for l in f:
            if l.startswith("VmRSS"): return int(l.split()[1])/1024
n = int(sys.argv[1]); H = int(sys.argv[2]); ne = int(sys.argv[3])
hf.nonlinear_mode(chain(12, ne), amplitude=(1e-3, 1e-1), points=4, harmonics=3)
s = chain(n, ne)
main = threading.main_thread().ident
log = []; stop = [False]; best=[0]
def sampler():
    while not stop[0]:
        r = rss()
        if r > best[0] + 15:
            st = traceback.extract_stack(sys._current_frames()[main])
            best[0] = r; log.append((r, " < ".join(f"{f.name}:{f.lineno}" for f in st[-7:][::-1])))
        time.sleep(0.002)
base = rss(); best[0]=base
th = threading.Thread(target=sampler, daemon=True); th.start()
hf.nonlinear_mode(s, amplitude=(1e-3, 1e-1), points=8, harmonics=H)
stop[0] = True; th.join()
for r, st in log: print(f"{r-base:7.0f} {st}")
