import os, sys, threading, time, traceback, warnings
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
sys.argv = [sys.argv[0]] + sys.argv[1:]
exec(open(".scratch/mem.py").read().split("what = sys.argv[1]")[0])
what = sys.argv[1]; n = int(sys.argv[2]); H = int(sys.argv[3])
s0 = chain(4); hf.frf(s0, 0.1, (0.3, 0.4), harmonics=3, condense=False)
s = chain(n)
main = threading.main_thread().ident
best = [0, None]; stop = [False]
def sampler():
    while not stop[0]:
        r = rss()
        if r > best[0] + 5:
            fr = sys._current_frames()[main]
            best[0] = r; best[1] = "".join(traceback.format_stack(fr)[-7:])
        time.sleep(0.005)
base = rss()
th = threading.Thread(target=sampler, daemon=True); th.start()
if what == "frf":
    hf.frf(s, 0.1, (0.3, 0.5), harmonics=H, condense=False, max_steps=30)
else:
    hf.periodic_solution(s, 0.1, 0.4, harmonics=H, condense=False)
stop[0] = True; th.join()
print("base", base, "peak", best[0], "delta", best[0]-base); print(best[1])
