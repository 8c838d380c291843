(NCQUAL PROGRAM machine=pm1 check=monument_positioning request=pm1-golden-1 dialect=linuxcnc units=mm work_offset=G54 touches=5 results=ncqual-pm1-golden-1.txt)
(NCQUAL VERSION ncqual test)
(probing program of daily 3: repeatable X, Y, Z positioning against the monument)
(X Y Z: the wrist pivot in G54 = machine coordinates - [0, 0, 0] mm; angles in degrees)
(tool length compensation off; no offset is changed; probe feed 100.0, approach 1000.0, safe Z 558.0000, the head turns at machine Z 1250.0000)
G21 G90 G94 G17 G40 G49
G54
(PROBEOPEN ncqual-pm1-golden-1.txt)
(from any state: up to machine Z 1250.0000, then the spindle and the head, in machine coordinates)
G53 G0 Z1250.0000
G53 G0 W0.0000
G53 G0 A0.0000 C0.0000
G0 X1200.0000 Y800.0000
G0 Z558.0000
(NCQUAL GUARD to=1200.0000,800.0000,495.0000)
G38.3 X1200.0000 Y800.0000 Z495.0000 F1000.0
o1001 if [#5070 NE 0]
  (ABORT, NCQUAL contact on the way down to touch 1: stopped)
o1001 endif
(NCQUAL TOUCH 1 feature=hole_edge approach=1,0,0 w=0.0000 a=0.0000 c=0.0000)
G38.2 X1227.0000 Y800.0000 Z495.0000 F100.0
G1 X1200.0000 Y800.0000 Z495.0000 F1000.0
(NCQUAL TOUCH 2 feature=hole_edge approach=0,1,0 w=0.0000 a=0.0000 c=0.0000)
G38.2 X1200.0000 Y827.0000 Z495.0000 F100.0
G1 X1200.0000 Y800.0000 Z495.0000 F1000.0
(NCQUAL TOUCH 3 feature=hole_edge approach=-1,0,0 w=0.0000 a=0.0000 c=0.0000)
G38.2 X1173.0000 Y800.0000 Z495.0000 F100.0
G1 X1200.0000 Y800.0000 Z495.0000 F1000.0
(NCQUAL TOUCH 4 feature=hole_edge approach=0,-1,0 w=0.0000 a=0.0000 c=0.0000)
G38.2 X1200.0000 Y773.0000 Z495.0000 F100.0
G1 X1200.0000 Y800.0000 Z495.0000 F1000.0
(NCQUAL GUARD to=1200.0000,800.0000,558.0000)
G38.3 X1200.0000 Y800.0000 Z558.0000 F1000.0
o1002 if [#5070 NE 0]
  (ABORT, NCQUAL contact on the way up after touch 4: stopped)
o1002 endif
G0 X1235.0000 Y800.0000
(NCQUAL GUARD to=1235.0000,800.0000,508.0000)
G38.3 X1235.0000 Y800.0000 Z508.0000 F1000.0
o1003 if [#5070 NE 0]
  (ABORT, NCQUAL contact on the way down to touch 5: stopped)
o1003 endif
(NCQUAL TOUCH 5 feature=face approach=0,0,-1 w=0.0000 a=0.0000 c=0.0000)
G38.2 X1235.0000 Y800.0000 Z498.0000 F100.0
G1 X1235.0000 Y800.0000 Z508.0000 F1000.0
(NCQUAL GUARD to=1235.0000,800.0000,558.0000)
G38.3 X1235.0000 Y800.0000 Z558.0000 F1000.0
o1004 if [#5070 NE 0]
  (ABORT, NCQUAL contact on the way up after touch 5: stopped)
o1004 endif
G53 G0 Z1250.0000
(PROBECLOSE)
M2
