"""Sphinx directives of the obturator docs: a command's ``--help`` and a gallery entry.

``obturator-help COMMAND``
    The command's help as ``obturator COMMAND --help`` prints it (from the one parser,
    :func:`obturator.cli.build_parser`), so a page never states options the code lacks.
``gallery-script PATH``
    A gallery entry: the script's docstring (first line the title), its source, and its
    figure. A script that sets ``RUN_IN_DOCS = True`` (a run of seconds) is executed by
    the build, which shows the figure it draws; the others (studies of minutes) show the
    committed PNG they wrote, named by their ``FIGURE``.
"""

from __future__ import annotations

import ast
import os
import runpy
import sys
from pathlib import Path

from docutils import nodes
from docutils.parsers.rst import Directive, directives


class ObturatorHelp(Directive):
    required_arguments = 1
    has_content = False

    def run(self) -> list[nodes.Node]:
        from obturator.cli import build_parser

        command = self.arguments[0]
        old = os.environ.get("COLUMNS")
        os.environ["COLUMNS"] = "88"  # argparse wraps to the terminal's width
        try:
            parser = build_parser(command, full=True)
            sub = next(a for a in parser._actions if a.dest == "command")
            text = sub.choices[command].format_help()  # type: ignore[attr-defined]
        finally:
            if old is None:
                os.environ.pop("COLUMNS", None)
            else:
                os.environ["COLUMNS"] = old
        block = nodes.literal_block(text, text)
        block["language"] = "text"
        return [block]


class GalleryScript(Directive):
    required_arguments = 1
    has_content = False

    def run(self) -> list[nodes.Node]:
        env = self.state.document.settings.env
        rel, path = env.relfn2path(self.arguments[0])
        env.note_dependency(rel)
        source = Path(path).read_text(encoding="utf-8")
        tree = ast.parse(source)
        doc = ast.get_docstring(tree) or ""
        names = {
            t.id: ast.literal_eval(node.value)
            for node in tree.body
            if isinstance(node, ast.Assign)
            for t in node.targets
            if isinstance(t, ast.Name) and t.id in ("FIGURE", "RUN_IN_DOCS")
        }
        title, _, text = doc.partition("\n")
        section = nodes.section(ids=[nodes.make_id(Path(path).stem)])
        section += nodes.title(title, title)
        for para in text.strip().split("\n\n"):
            section += nodes.paragraph(para, " ".join(para.split()))
        figure = names["FIGURE"]
        src_dir = Path(env.srcdir)
        if names.get("RUN_IN_DOCS"):
            out = src_dir / "_generated"
            out.mkdir(exist_ok=True)
            argv = sys.argv
            sys.argv = [path, str(out)]
            try:
                runpy.run_path(path, run_name="__main__")
            finally:
                sys.argv = argv
            image = "/_generated/" + figure
            note = "Drawn by the documentation build from the script below."
        else:
            image = "/" + figure
            note = "The committed figure; the script below regenerates it (a study of minutes)."
        section += nodes.image(uri=image, alt=title)
        section += nodes.paragraph(note, note)
        block = nodes.literal_block(source, source)
        block["language"] = "python"
        section += block
        return [section]


def setup(app):  # noqa: ANN001, ANN201 - the Sphinx extension hook
    directives.register_directive("obturator-help", ObturatorHelp)
    directives.register_directive("gallery-script", GalleryScript)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
