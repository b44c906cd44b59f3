#!/usr/bin/env python3
# A model of the spectral MIS of media/scattering.h, for the study in docs/performance.md
# ("Colour noise in chromatic media"). A white furnace: a ball (radius 1, index-matched) of a
# medium that scatters without absorbing, sigma_s per wavelength (in units of the radius), HG
# phase g, camera rays entering near its middle; every wavelength's true radiance is 1 (each path
# that leaves sees the background, 1). Estimators of the K wavelengths from one path:
#   mis:       the hero drawn uniformly per path, its delta tracking, every wavelength weighted by
#              the one-sample balance heuristic p_k / mean_j p_j (Bouguer before #20);
#   mis_strat: the same with the hero stratified over a pixel's samples (Bouguer now);
#   keep:      mis_strat, keeping the hero alone (K times its analog weight) after the first
#              scattering event;
#   spectral:  spectral tracking (Kutz, Habel, Li & Novak 2017): majorant max_k sigma_k, collision
#              probabilities from the throughput, P_real = mean(beta*sigma) / mean(beta*sigma_max).
# Prints the standard deviation of a pixel's mean (S samples) per wavelength, and the tentative
# collisions per path (the cost). Usage:
#   bench/spectral_mis_model.py 1.8,1.2,0.72,0.36 0.7 300 16 mis,mis_strat,keep,spectral
import math, random, sys
def hg(g, rnd):
    u = rnd.random()
    if abs(g) < 1e-3: return 1 - 2*u
    s = (1 - g*g) / (1 - g + 2*g*u)
    return (1 + g*g - s*s) / (2*g)
def turn(d, cos_t, rnd):
    sin_t = math.sqrt(max(0.0, 1 - cos_t*cos_t)); phi = 2*math.pi*rnd.random()
    x, y, z = d
    if abs(z) < 0.9: a = (0, 0, 1)
    else: a = (1, 0, 0)
    # frame
    t = (a[1]*z - a[2]*y, a[2]*x - a[0]*z, a[0]*y - a[1]*x); n = math.sqrt(sum(c*c for c in t)); t = tuple(c/n for c in t)
    b = (y*t[2] - z*t[1], z*t[0] - x*t[2], x*t[1] - y*t[0])
    return tuple(sin_t*math.cos(phi)*t[i] + sin_t*math.sin(phi)*b[i] + cos_t*d[i] for i in range(3))
def exit_dist(p, d):
    b = sum(p[i]*d[i] for i in range(3)); c = sum(p[i]*p[i] for i in range(3)) - 1
    return -b + math.sqrt(max(0.0, b*b - c))
def start(rnd):
    r = 0.3*math.sqrt(rnd.random()); a = 2*math.pi*rnd.random()
    x, y = r*math.cos(a), r*math.sin(a)
    return (x, y, -math.sqrt(1 - x*x - y*y)), (0.0, 0.0, 1.0)
def path_mis(sig, g, hero, rnd, keep=False):
    K = len(sig); p, d = start(rnd); n = 0; M = 0.0; cost = 0
    while True:
        t_exit = exit_dist(p, d); t = -math.log(1 - rnd.random()) / sig[hero]; cost += 1
        if t >= t_exit:
            M += t_exit; break
        M += t; n += 1
        if keep:  # from here on the hero alone: its analog weight (1 in a furnace), K times
            return [K*1.0 if k == hero else 0.0 for k in range(K)], cost + walk_rest(sig[hero], g, p, d, t, rnd)
        p = tuple(p[i] + t*d[i] for i in range(3)); d = turn(d, hg(g, rnd), rnd)
    logp = [n*math.log(s) - s*M for s in sig]; m = max(logp)
    pk = [math.exp(l - m) for l in logp]; mean = sum(pk)/K
    return [x/mean for x in pk], cost
def walk_rest(s, g, p, d, t, rnd):
    p = tuple(p[i] + t*d[i] for i in range(3)); d = turn(d, hg(g, rnd), rnd); cost = 0
    while True:
        t_exit = exit_dist(p, d); t = -math.log(1 - rnd.random()) / s; cost += 1
        if t >= t_exit: return cost
        p = tuple(p[i] + t*d[i] for i in range(3)); d = turn(d, hg(g, rnd), rnd)
def path_spectral(sig, g, rnd):
    K = len(sig); smax = max(sig); p, d = start(rnd); beta = [1.0]*K; cost = 0
    while True:
        t_exit = exit_dist(p, d); t = -math.log(1 - rnd.random()) / smax; cost += 1
        if t >= t_exit: break
        p = tuple(p[i] + t*d[i] for i in range(3))
        ps = sum(b*s for b, s in zip(beta, sig)) / (smax*sum(beta))
        if rnd.random() < ps:
            beta = [b*s/(smax*ps) for b, s in zip(beta, sig)]; d = turn(d, hg(g, rnd), rnd)
        else:
            beta = [b*(smax - s)/(smax*(1 - ps)) for b, s in zip(beta, sig)]
    return beta, cost
def run(method, sig, g, pixels, S, seed):
    rnd = random.Random(seed); K = len(sig); means = []; cost = 0
    for px in range(pixels):
        acc = [0.0]*K; perm = list(range(K)); off = rnd.randrange(K)
        for s in range(S):
            if method == 'spectral': b, c = path_spectral(sig, g, rnd)
            else:
                hero = (s + off) % K if method in ('mis_strat', 'keep') else rnd.randrange(K)
                b, c = path_mis(sig, g, hero, rnd, method == 'keep')
            cost += c; acc = [a + x for a, x in zip(acc, b)]
        means.append([a/S for a in acc])
    sd = [math.sqrt(sum((m[k] - 1)**2 for m in means)/len(means)) for k in range(K)]
    return sd, cost/(pixels*S)
if __name__ == '__main__':
    sig = [float(x) for x in sys.argv[1].split(',')]; g = float(sys.argv[2]); pixels = int(sys.argv[3]); S = int(sys.argv[4])
    for method in sys.argv[5].split(','):
        sd, c = run(method, sig, g, pixels, S, 7)
        print('%-9s sd of a pixel mean per wavelength: %s; collisions/path %.1f' % (method, ' '.join('%.4f' % x for x in sd), c))
