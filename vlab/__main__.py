from vlab.cli import app

app(prog_name="vlab")
