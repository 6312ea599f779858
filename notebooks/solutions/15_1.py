# (8 + 3.5 + 7 + 3.5) characters of 10 bits at 9600 baud, in milliseconds.
answer = 22 * 10 / 9600 * 1000
