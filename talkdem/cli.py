def main() -> None:
    print("talkdem")
