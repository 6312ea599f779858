# Holding 20 (one FC 3), input 0-11, 52-53 and 70-73 (three FC 4): four requests.
answer = 4
