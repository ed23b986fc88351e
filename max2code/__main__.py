from max2code.cli import run

run()
