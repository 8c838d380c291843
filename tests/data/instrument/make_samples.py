#!/usr/bin/env python3
# Writes the sample instrument exports of this folder (deterministic: fixed seed). Run it here:
#   python3 make_samples.py
# The injected errors are written beside each block; tests/data/README.md lists them.
import math, random
random.seed(20261124)
# ISO 230-2: X axis 0..1000 mm, 11 targets, 5 cycles, up/down. Pitch error 8 um/m slope,
# a 3 um sine of period 400 mm, backlash 4 um, repeatability 0.7 um (1 sigma).
with open("iso230-2_x.csv","w") as f:
    f.write("# sample interferometer export, X axis, 11 targets x 5 cycles, bidirectional\n")
    f.write("target_mm,cycle,direction,measured_mm,air_C\n")
    for c in range(1,6):
        for d in ("up","down"):
            ts = [100.0*i for i in range(11)]
            if d == "down": ts.reverse()
            for t in ts:
                e = 8e-6*t + 3e-3*math.sin(2*math.pi*t/400.0) + (0.002 if d=="up" else -0.002) + random.gauss(0,0.0007)
                f.write("%.0f,%d,%s,%.5f,20.1\n" % (t,c,d,t+e))
# Circle XY, 150 mm radius, 360 points each way, squareness 20 urad and a scale mismatch of 15 um/m,
# reversal 2 um on the x axis.
with open("circle_xy.csv","w") as f:
    f.write("# sample ballbar-like export, XY plane, nominal radius 150 mm, both directions\n")
    f.write("x_mm,y_mm,direction\n")
    R=150.0
    for d in ("ccw","cw"):
        for k in range(360):
            a = math.radians(k if d=="ccw" else -k)
            x = R*math.cos(a); y = R*math.sin(a)
            xm = x*(1+15e-6) + 20e-6*y + (0.001 if d=="ccw" else -0.001) + random.gauss(0,0.0004)
            ym = y + random.gauss(0,0.0004)
            f.write("%.5f,%.5f,%s\n" % (xm,ym,d))
# Grid: tracker frame rotated 90 deg about Z and shifted; machine with xy squareness 30 urad,
# x scale 12 um/m.
def meas(x,y,z):
    xt = x*(1+12e-6) + 30e-6*y
    yt = y; zt = z
    # tracker frame: Rz(90): (x,y)->(y,-x) after moving origin to (2200,-2500,1000)
    px,py,pz = xt-2200, yt+2500, zt-1000
    return (py + random.gauss(0,0.003), -px + random.gauss(0,0.003), pz + random.gauss(0,0.003))
def line(f,name,x,y,z):
    m = meas(x,y,z)
    f.write("%s,%.3f,%.3f,%.3f,%.4f,%.4f,%.4f\n" % (name,x,y,z,m[0],m[1],m[2]))
H="point,x_cmd,y_cmd,z_cmd,x_meas,y_meas,z_meas\n"
with open("grid_x_run.csv","w") as f:
    f.write(H)
    for i in range(11): line(f,"x%d"%i,200+400*i,950,900)
with open("grid_y_run.csv","w") as f:
    f.write(H)
    for i in range(10): line(f,"y%d"%i,2200,200+150*i,900)
with open("grid.csv","w") as f:
    f.write(H); n=0
    for z in (600,800,1000,1200):
        for j in range(6):
            for i in range(9):
                line(f,"g%d"%n,200+500*i,200+300*j,z); n+=1
