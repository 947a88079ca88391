"""Reference coefficients of scipy.signal.butter(2, Wn) (second-order low-pass, Wn normalized
to the Nyquist frequency) for the F/T filter test of corps-estimation
(crates/corps-estimation/src/lowpass.rs). Usage: pip install scipy; python3 tools/golden/butterworth.py"""
from scipy.signal import butter

for wn in (0.4, 0.1):
    b, a = butter(2, wn)
    print(f"Wn = {wn}: b = {[float(x) for x in b]}, a = {[float(x) for x in a]}")
