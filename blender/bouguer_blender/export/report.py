"""What the translation could not carry over: each message once, for Blender's report."""


class Reports:
    def __init__(self):
        self.warnings = []

    def warn(self, message):
        if message not in self.warnings:
            self.warnings.append(message)
