from voe.cli.main import main

main()
