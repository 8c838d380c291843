(NCQUAL PROGRAM machine=pm1 check=monument_positioning request=pm1-golden-1 dialect=generic-csv units=mm work_offset=G54 touches=5 results=ncqual-pm1-golden-1.csv)
(NCQUAL VERSION ncqual test)
(probing program of daily 3: repeatable X, Y, Z positioning against the monument)
(X Y Z: the wrist pivot in G54 = machine coordinates - [0, 0, 0] mm; angles in degrees)
(tool length compensation off; no offset is changed; probe feed 100.0, approach 1000.0, safe Z 558.0000, the head turns at machine Z 1250.0000)
G21 G90 G94 G17 G40 G49
G54
(after each G31 the control writes n,x,y,z [pivot, program units] to ncqual-pm1-golden-1.csv)
(from any state: up to machine Z 1250.0000, then the spindle and the head, in machine coordinates)
G53 G0 Z1250.0000
G53 G0 W0.0000
G53 G0 A0.0000 C0.0000
G0 X1200.0000 Y800.0000
G0 Z558.0000
G1 X1200.0000 Y800.0000 Z495.0000 F1000.0
(NCQUAL TOUCH 1 feature=hole_edge approach=1,0,0 w=0.0000 a=0.0000 c=0.0000)
G31 X1227.0000 Y800.0000 Z495.0000 F100.0
(NCQUAL LOG 1)
G1 X1200.0000 Y800.0000 Z495.0000 F1000.0
(NCQUAL TOUCH 2 feature=hole_edge approach=0,1,0 w=0.0000 a=0.0000 c=0.0000)
G31 X1200.0000 Y827.0000 Z495.0000 F100.0
(NCQUAL LOG 2)
G1 X1200.0000 Y800.0000 Z495.0000 F1000.0
(NCQUAL TOUCH 3 feature=hole_edge approach=-1,0,0 w=0.0000 a=0.0000 c=0.0000)
G31 X1173.0000 Y800.0000 Z495.0000 F100.0
(NCQUAL LOG 3)
G1 X1200.0000 Y800.0000 Z495.0000 F1000.0
(NCQUAL TOUCH 4 feature=hole_edge approach=0,-1,0 w=0.0000 a=0.0000 c=0.0000)
G31 X1200.0000 Y773.0000 Z495.0000 F100.0
(NCQUAL LOG 4)
G1 X1200.0000 Y800.0000 Z495.0000 F1000.0
G1 X1200.0000 Y800.0000 Z558.0000 F1000.0
G0 X1235.0000 Y800.0000
G1 X1235.0000 Y800.0000 Z508.0000 F1000.0
(NCQUAL TOUCH 5 feature=face approach=0,0,-1 w=0.0000 a=0.0000 c=0.0000)
G31 X1235.0000 Y800.0000 Z498.0000 F100.0
(NCQUAL LOG 5)
G1 X1235.0000 Y800.0000 Z508.0000 F1000.0
G1 X1235.0000 Y800.0000 Z558.0000 F1000.0
G53 G0 Z1250.0000
M2
