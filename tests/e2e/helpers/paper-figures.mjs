// The paper's Fig. 3 (GBASIC) and Fig. 2, the GLOC the paper says it compiles to.
export const fig3 = `label: state1
if m_depth > 15.0 then
  SCI_RUHP_BEHS = 128
  goto state2
endif
yield
goto state1
label: state2
if m_depth < 5.0 then
  SCI_RUHP_BEHS = 0
  goto state3
endif
yield
goto state2
label: state3
yield
goto state3
`;
export const fig2 = `nregs 8
nblbs 7
ninstr 27
label 0
loads 444,r0
loadd 15.0,r1
cmpgt r0,r1,r2
cbr r2,3,4
label 3
loadi 128,r3
stores r3,1387
jumpi 1
label 4
yield
jumpi 0
label 1
loads 444,r4
loadd 5.0,r5
cmplt r4,r5,r6
cbr r6,5,6
label 5
loadi 0,r7
stores r7,1387
jumpi 2
label 6
yield
jumpi 1
label 2
yield
jumpi 2
`;
