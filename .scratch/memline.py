import os, sys, threading, time, traceback, warnings
exec(open(".scratch/mem.py").read().split("what = sys.argv[1]")[0])
what = sys.argv[1]; n = int(sys.argv[2]); H = int(sys.argv[3])
s0 = chain(12); hf.frf(s0, 0.1, (0.3, 0.4), harmonics=3, condense=False)
s = chain(n)
main = threading.main_thread().ident
log = []; stop = [False]; best=[0]
def sampler():
    while not stop[0]:
        r = rss()
        if r > best[0] + 40:
            fr = sys._current_frames()[main]
            st = traceback.extract_stack(fr)
            best[0] = r; log.append((r, " < ".join(f"{f.name}:{f.lineno}" for f in st[-6:][::-1])))
        time.sleep(0.003)
base = rss(); best[0]=base
th = threading.Thread(target=sampler, daemon=True); th.start()
if what == "frf":
    hf.frf(s, 0.1, (0.3, 0.5), harmonics=H, condense=False, max_steps=30)
else:
    hf.periodic_solution(s, 0.1, 0.4, harmonics=H, condense=False)
stop[0] = True; th.join()
print("base", base)
for r, st in log: print(f"{r-base:7.0f} {st}")
