"""`motionvm studio`: the browser studio on 127.0.0.1, until Ctrl-C (exit 0)."""

from __future__ import annotations

import sys

from motionvm.cli.exits import UsageError


def cmd_studio(args) -> int:
    import asyncio
    import webbrowser

    from motionvm.session import SessionError, load_machine_spec
    from motionvm.studio import Studio
    from motionvm.studio.app import bind, new_token, serve
    from motionvm.studio.workspace import WorkspaceError

    try:
        if args.machine is not None:
            load_machine_spec(args.machine)
        studio = Studio(list(args.files), machine=args.machine, scenario=args.scenario)
    except (SessionError, WorkspaceError) as exc:
        raise UsageError(str(exc)) from None
    try:
        sock = bind(args.port)
    except OSError as exc:
        raise UsageError(f"--port {args.port}: {exc.strerror or exc}") from None
    token = new_token()

    def ready(url: str) -> None:
        print(f"motionvm studio: {url}", file=sys.stderr, flush=True)
        if not args.no_browser:
            webbrowser.open(url)

    try:
        asyncio.run(serve(studio, sock, token, ready))
    except KeyboardInterrupt:
        pass
    return 0
